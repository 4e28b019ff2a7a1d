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
 * @file arch/linux/modules/ranging/ranging_can.h
 * Ranging units on a CAN bus, read through SocketCAN: one raw socket bound to the interface of the airframe
 * (RANGING_CAN_IFNAME, "can0"), kernel filters passing the ranging ids only (frame layout in
 * modules/ranging/ranging_can_frame.h), error frames enabled, non-blocking reads in the module's event
 * function. What the frames mean (peer table, sequence gaps, stale peers, bus-off and restarts) is the pure
 * logic of modules/ranging/ranging_can_rx.h; this file only moves frames from the socket into it.
 *
 * Recovery: the kernel restarts a controller after bus-off when the interface has restart-ms set
 * (`ip link set can0 type can restart-ms 100`); the driver reports the bus-off and the restart (stats). An
 * interface taken down makes one read fail with ENETDOWN (reported; the socket stays and reads on when the
 * interface is up again). A socket that fails otherwise (the interface was removed) is closed and reopened
 * every RANGING_CAN_REOPEN_MS while the event function runs.
 *
 * The seam: ranging_can_open_fd() takes any descriptor carrying one struct can_frame / canfd_frame per
 * message (a socketpair in tests, fed by hand or from a candump log with ranging_can_replay.h); everything
 * above it is the code that runs on the copter. Kernel filters cannot be set on such a descriptor: the
 * driver checks every frame itself anyway.
 */

#ifndef RANGING_CAN_H
#define RANGING_CAN_H

#include "modules/ranging/ranging_can_rx.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** CAN interface of the ranging units (airframe define) */
#ifndef RANGING_CAN_IFNAME
#define RANGING_CAN_IFNAME "can0"
#endif
/** A peer's distance older than this is stale [ms] */
#ifndef RANGING_CAN_STALE_MS
#define RANGING_CAN_STALE_MS 500
#endif
/** Most frames read in one ranging_can_event() (bounds the time spent in the main loop) */
#ifndef RANGING_CAN_MAX_FRAMES_PER_EVENT
#define RANGING_CAN_MAX_FRAMES_PER_EVENT 256
#endif
/** Retry period for a socket that failed [ms] */
#ifndef RANGING_CAN_REOPEN_MS
#define RANGING_CAN_REOPEN_MS 1000
#endif

struct ranging_can;

struct ranging_can_config {
  const char *ifname;                ///< CAN interface (ranging_can_open() only)
  struct ranging_can_rx_config rx;   ///< frame layout, this copter's id, staleness
  unsigned max_frames_per_event;     ///< frames read per ranging_can_event() at most (> 0)
};

struct ranging_can_stats {
  struct ranging_can_rx_stats rx;        ///< what the frames were (see ranging_can_rx.h)
  enum ranging_can_bus_state bus_state;  ///< from the error frames
  unsigned stale_peers;                  ///< peers heard but stale at the last event
  uint32_t malformed;                    ///< messages of the wrong size (seam only: a CAN socket never has them)
  uint32_t kernel_drops;                 ///< frames the kernel dropped because the socket was full
  uint32_t read_errors;                  ///< failed reads (ENETDOWN, a removed interface, ...)
  uint32_t reopens;                      ///< sockets reopened after a failure
};

/** Called for each distance about this copter. */
typedef void (*ranging_can_reading_cb)(void *user, const struct ranging_can_reading *reading);

/**
 * Open a CAN socket on cfg->ifname with the ranging filters and error frames.
 * @param err receives one message on failure naming the interface and the errno text, e.g. "CAN interface
 *        'can0': cannot create a SocketCAN socket: Address family not supported by protocol (...)", or the
 *        configuration field that is wrong
 * @return the driver, or NULL with errno set (EINVAL: bad configuration)
 */
extern struct ranging_can *ranging_can_open(const struct ranging_can_config *cfg, char *err, size_t errlen);

/** The driver on a descriptor from elsewhere (the seam); it takes the descriptor (closed by ranging_can_close()). */
extern struct ranging_can *ranging_can_open_fd(int fd, const struct ranging_can_config *cfg, char *err,
    size_t errlen);

/**
 * Read the frames that arrived (at most max_frames_per_event), without blocking, at now_us (the caller's
 * clock: each reading is stamped with its kernel reception time on that clock).
 * @param cb called for each distance about this copter (may be NULL)
 * @return the number of readings, or -1 with errno when the socket failed (see ranging_can_last_error())
 */
extern int ranging_can_event(struct ranging_can *rc, uint32_t now_us, ranging_can_reading_cb cb, void *user);

/** The newest distance to other_id: 1 fresh, 0 stale (*out filled), -1 never heard (see ranging_can_rx_peer()). */
extern int ranging_can_peer(const struct ranging_can *rc, uint8_t other_id, uint32_t now_us,
                            struct ranging_can_reading *out);

/** Counters and bus state. */
extern void ranging_can_stats(const struct ranging_can *rc, struct ranging_can_stats *out);

/** The last socket error message ("" if none). */
extern const char *ranging_can_last_error(const struct ranging_can *rc);

/** The socket descriptor (-1 while reopening). */
extern int ranging_can_fd(const struct ranging_can *rc);

/** Close; NULL is a no-op. */
extern void ranging_can_close(struct ranging_can *rc);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_CAN_H */
