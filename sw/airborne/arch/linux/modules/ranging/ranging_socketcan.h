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
 * @file arch/linux/modules/ranging/ranging_socketcan.h
 * The ranging driver's raw SocketCAN sockets (its own, not Paparazzi's CAN peripheral): open and bind with kernel
 * filters and error frames, adopt a descriptor from elsewhere (the test seam: a socketpair), non-blocking reads
 * with the kernel's reception time stamp and drop counter, non-blocking writes (the candump replay).
 *
 * Every descriptor is non-blocking and close-on-exec. Receive time stamps are the kernel's (SO_TIMESTAMPNS,
 * CLOCK_REALTIME); ranging_socketcan_read() turns them into an age at the time of the read, which callers
 * subtract from their own clock. Errors: -1 with errno set, and for ranging_socketcan_open() one message naming
 * the interface, what failed and the errno text.
 */

#ifndef RANGING_SOCKETCAN_H
#define RANGING_SOCKETCAN_H

#include <linux/can.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct ranging_socketcan_config {
  const struct can_filter *filters;  ///< kernel filters (CAN_RAW_FILTER); NULL: every data frame
  unsigned nb_filters;
  can_err_mask_t err_mask;           ///< error classes to receive (CAN_RAW_ERR_FILTER); 0: none
  bool fd_frames;                    ///< also receive and send CAN FD frames (CAN_RAW_FD_FRAMES)
};

/** One received frame. */
struct ranging_socketcan_rx {
  struct canfd_frame frame;  ///< a classical frame uses the first CAN_MTU bytes (len <= 8)
  bool fd;                   ///< a CAN FD frame
  uint64_t age_ns;           ///< time from the kernel's reception stamp to the read [ns], 0 without a stamp
  bool has_drops;            ///< drops is valid
  uint32_t drops;            ///< frames the kernel dropped on this socket so far (SO_RXQ_OVFL)
};

/**
 * Open a raw CAN socket bound to ifname.
 * @param err receives one message on failure, e.g. "CAN interface 'can0': cannot create a SocketCAN socket:
 *        Address family not supported by protocol (...)"
 * @return the descriptor, or -1 with errno set
 */
extern int ranging_socketcan_open(const char *ifname, const struct ranging_socketcan_config *cfg, char *err,
                                  size_t errlen);

/**
 * Make a descriptor from elsewhere (a socketpair end carrying one frame per message) behave as an opened
 * one: non-blocking, close-on-exec, reception time stamps. Returns 0, or -1 with errno and err set.
 */
extern int ranging_socketcan_adopt(int fd, char *err, size_t errlen);

/**
 * Read one frame without blocking.
 * @return 1 a frame in *rx; 0 none pending; -1 with errno: EBADMSG a message of the wrong size or a length
 *         out of range (skipped: read on), EPIPE the other end closed, else the read's error
 */
extern int ranging_socketcan_read(int fd, struct ranging_socketcan_rx *rx);

/** Send one frame without blocking (fd_frame: as CAN FD); -1 with errno (EAGAIN/ENOBUFS: transmit queue full). */
extern int ranging_socketcan_write(int fd, const struct canfd_frame *frame, bool fd_frame);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_SOCKETCAN_H */
