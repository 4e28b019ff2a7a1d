/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file modules/core/abi_common.h
 * Host stand-in for Paparazzi's ABI common definitions (same event structure and macros); the queues are per simulated vehicle.
 */

#ifndef ABI_COMMON_H
#define ABI_COMMON_H

#include "std.h"
#include "math/pprz_algebra_float.h"
#include "modules/core/abi_sender_ids.h"

/** Generic callback definition */
typedef void (*abi_callback)(void);

/** Bind with this sender id to receive the message from every sender. */
#define ABI_BROADCAST 255
/** Bind with this sender id to disable the callback. */
#define ABI_DISABLE 0

/** Event structure to store callbacks in a linked list */
struct abi_struct {
  uint8_t id;
  abi_callback cb;
  struct abi_struct *next;
};
typedef struct abi_struct abi_event;

#define ABI_FOREACH(head,el) for(el=head; el; el=el->next)
#define ABI_PREPEND(head,add) { (add)->next = head; head = add; }

/** The message queues (ABI_MESSAGE_NB of them) of the vehicle the host is running now. */
extern abi_event **abi_queues_current(void);

#endif /* ABI_COMMON_H */
