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
 * @file arch/linux/modules/sonar/sonar_gpiod.h
 * The sonar driver's GPIO lines through the GPIO character device with libgpiod 1.x (1.4 to 1.6): the only
 * file of the sonar module that calls libgpiod. libgpiod 2.x has another API; sonar_gpiod.c refuses it at
 * compile time with a message saying so.
 *
 * A line is requested as an output (the trigger) or as an input with both-edge events (the echo); edge events
 * carry the kernel's time stamp (CLOCK_MONOTONIC since Linux 5.7, CLOCK_REALTIME before; only differences of two
 * stamps should be used). Chips are named as libgpiod's lookup accepts them: "gpiochip0", "0", "/dev/gpiochip0"
 * or the chip label. Errors: NULL or -1 with errno set, and for requests one message naming the chip, the line
 * and the errno text.
 */

#ifndef SONAR_GPIOD_H
#define SONAR_GPIOD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct sonar_gpiod_line;

enum sonar_gpiod_mode {
  SONAR_GPIOD_OUTPUT,      ///< driven by sonar_gpiod_set()
  SONAR_GPIOD_BOTH_EDGES,  ///< input with rising and falling edge events on sonar_gpiod_event_fd()
};

/** One edge event. */
struct sonar_gpiod_edge {
  uint64_t t_ns;  ///< kernel time stamp [ns]
  bool rising;    ///< rising (true) or falling edge
};

/**
 * Request line `offset` of `chip` for `consumer` (the label gpioinfo shows).
 * @param initial output level (SONAR_GPIOD_OUTPUT only)
 * @param err receives one message on failure, e.g. "gpiochip 'gpiochip9' line 4: cannot open the chip: No such
 *        file or directory"
 * @return the line, or NULL with errno set
 */
extern struct sonar_gpiod_line *sonar_gpiod_request(const char *chip, unsigned offset, enum sonar_gpiod_mode mode,
    int initial, const char *consumer, char *err, size_t errlen);

/** Drive an output line (0 or 1); -1 and errno on failure. */
extern int sonar_gpiod_set(struct sonar_gpiod_line *line, int value);

/** The non-blocking event file descriptor of a SONAR_GPIOD_BOTH_EDGES line (-1 for other modes). */
extern int sonar_gpiod_event_fd(const struct sonar_gpiod_line *line);

/**
 * Read up to max pending edge events from an event file descriptor without blocking.
 * The descriptor delivers the kernel's struct gpioevent_data records (what sonar_gpiod_event_fd() returns, or a
 * pipe a test writes such records into).
 * @return the number of events read (0 if none is pending), or -1 with errno set (EIO: a truncated record)
 */
extern int sonar_gpiod_read_edges(int fd, struct sonar_gpiod_edge *edges, unsigned max);

/** Release the line and its chip; NULL is a no-op. */
extern void sonar_gpiod_release(struct sonar_gpiod_line *line);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_GPIOD_H */
