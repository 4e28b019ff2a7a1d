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
 * @file arch/linux/mcu_periph/can_arch.h
 * Paparazzi's CAN peripheral (mcu_periph/can.h) for Linux over SocketCAN.
 *
 * can1 is the interface CAN1_IFNAME ("can0" by default), can2 (USE_CAN2) CAN2_IFNAME ("can1"); in
 * struct pprzaddr_can they are can_ifindex 1 and 2, as on the other architectures (0: all). The interface is
 * set up outside Paparazzi, e.g. `ip link set can0 up type can bitrate 1000000 restart-ms 100`.
 *
 * can_hw_init() (through can_init()) opens and binds one raw socket per interface: every data frame, CAN FD
 * frames too (CAN_FD_MODE), no error frames. Reception never blocks: can_event(), called from the main loop
 * (a module's event function), reads what arrived and calls the registered callbacks with each frame; the
 * frame's timestamp is the kernel's reception time on get_sys_time_usec()'s clock [us].
 * can_transmit_frame() sends without blocking: 0, or -1 with errno (EAGAIN/ENOBUFS: transmit queue full,
 * EINVAL: bad frame, ENODEV: interface not open).
 *
 * Errors (an interface that cannot be opened, a failing read) give one message naming the interface and the
 * errno text to the error sink (stderr by default) and can_arch_last_error(); they are not repeated.
 */

#ifndef CAN_ARCH_H
#define CAN_ARCH_H

#include "std.h"

/** A Linux autopilot uses its first CAN interface unless the airframe says otherwise */
#ifndef USE_CAN1
#define USE_CAN1 TRUE
#endif
/** Interface of can1 */
#ifndef CAN1_IFNAME
#define CAN1_IFNAME "can0"
#endif
/** Interface of can2 (USE_CAN2) */
#ifndef CAN2_IFNAME
#define CAN2_IFNAME "can1"
#endif
/** Most frames read per interface in one can_event() (bounds the time spent in the main loop) */
#ifndef CAN_ARCH_MAX_FRAMES_PER_EVENT
#define CAN_ARCH_MAX_FRAMES_PER_EVENT 64
#endif

/** Open the interfaces (called by can_init()). */
extern void can_hw_init(void);

/** Read the frames that arrived and call the callbacks; never blocks. */
extern void can_event(void);

/* Linux only */

/**
 * The test seam: use fd (e.g. a socketpair end carrying one struct can_frame or canfd_frame per message)
 * as interface can_ifindex (1 or 2) instead of a CAN socket. Returns 0, or -1 with errno.
 */
extern int can_arch_attach_fd(int can_ifindex, int fd);

/** Close the interfaces (at shutdown, or between tests). */
extern void can_arch_close(void);

/** The last error message ("" if none). */
extern const char *can_arch_last_error(void);

/** Where error messages go (NULL: stderr). */
extern void can_arch_set_error_sink(void (*sink)(const char *msg));

#endif /* CAN_ARCH_H */
