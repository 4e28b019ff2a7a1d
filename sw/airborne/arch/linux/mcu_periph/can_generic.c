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
 * @file arch/linux/mcu_periph/can_generic.c
 * The architecture independent part of Paparazzi's CAN peripheral (what Paparazzi's mcu_periph/can.c holds:
 * the peripherals, can_init, the callback table, DLC <-> length), for Linux builds outside a Paparazzi tree.
 * In a Paparazzi tree, leave this file out: mcu_periph/can.c defines the same symbols.
 */

#include "mcu_periph/can.h"

#include <errno.h>
#include <stddef.h>

#if USE_CAN1
struct can_periph can1 = { .arch_struct = NULL, .fd = -1 };
#endif
#if USE_CAN2
struct can_periph can2 = { .arch_struct = NULL, .fd = -1 };
#endif

/** Payload length of each DLC (ISO 11898-1:2015: DLC 9 to 15 are CAN FD lengths 12 to 64) */
static const uint8_t dlc_to_len[16] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64 };

uint8_t can_dlc_to_len(uint8_t dlc)
{
  return dlc < 16 ? dlc_to_len[dlc] : 0;
}

uint8_t can_len_to_dlc(uint8_t len)
{
  for (uint8_t dlc = 0; dlc < 16; dlc++) {
    if (dlc_to_len[dlc] >= len) {
      return dlc;
    }
  }
  return 15;
}

void can_init(void)
{
  can_hw_init();
}

static int add_callback(struct can_periph *p, can_rx_frame_callback_t callback, void *user_data)
{
  for (int i = 0; i < CAN_NB_CALLBACKS_MAX; i++) {
    if (p->callbacks[i] == NULL) {
      p->callbacks[i] = callback;
      p->callback_user_data[i] = user_data;
      return 0;
    }
  }
  errno = ENOSPC;
  return -1;
}

int can_register_callback(can_rx_frame_callback_t callback, struct pprzaddr_can *src_addr, void *user_data)
{
  const int ifindex = src_addr != NULL ? src_addr->can_ifindex : 0;
  int matched = 0;
#if USE_CAN1
  if (ifindex == 0 || ifindex == 1) {
    if (add_callback(&can1, callback, user_data) != 0) {
      return -1;
    }
    matched++;
  }
#endif
#if USE_CAN2
  if (ifindex == 0 || ifindex == 2) {
    if (add_callback(&can2, callback, user_data) != 0) {
      return -1;
    }
    matched++;
  }
#endif
  if (matched == 0) {
    errno = ENODEV;
    return -1;
  }
  return 0;
}
