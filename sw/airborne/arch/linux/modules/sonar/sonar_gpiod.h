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
 * @file arch/linux/mcu_periph/gpiod_io.h
 * GPIO lines through the GPIO character device with libgpiod 1.6: the only file that calls libgpiod, so a
 * move to libgpiod 2.x changes gpiod_io.c alone.
 *
 * A line is requested as output, input, or input with both-edge events; edge events carry the kernel's time
 * stamp (CLOCK_MONOTONIC since Linux 5.7, CLOCK_REALTIME before; only differences of two stamps should be used).
 * Chips are named as libgpiod's lookup accepts them: "gpiochip0", "0", "/dev/gpiochip0" or the chip label.
 * Errors: NULL or -1 with errno set, and for requests one message naming the chip, the line and the errno text.
 */

#ifndef GPIOD_IO_H
#define GPIOD_IO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct gpiod_io_line;

enum gpiod_io_mode {
  GPIOD_IO_OUTPUT,      ///< driven by gpiod_io_set()
  GPIOD_IO_INPUT,       ///< read by gpiod_io_get()
  GPIOD_IO_BOTH_EDGES,  ///< input with rising and falling edge events on gpiod_io_event_fd()
};

/** One edge event. */
struct gpiod_io_edge {
  uint64_t t_ns;  ///< kernel time stamp [ns]
  bool rising;    ///< rising (true) or falling edge
};

/**
 * Request line `offset` of `chip` for `consumer` (the label gpioinfo shows).
 * @param initial output level (GPIOD_IO_OUTPUT only)
 * @param err receives one message on failure, e.g. "gpiochip 'gpiochip9' line 4: cannot open the chip: No such
 *        file or directory"
 * @return the line, or NULL with errno set
 */
extern struct gpiod_io_line *gpiod_io_request(const char *chip, unsigned offset, enum gpiod_io_mode mode,
    int initial, const char *consumer, char *err, size_t errlen);

/** Drive an output line (0 or 1); -1 and errno on failure. */
extern int gpiod_io_set(struct gpiod_io_line *line, int value);

/** Read a line's level (0 or 1); -1 and errno on failure. */
extern int gpiod_io_get(struct gpiod_io_line *line);

/** The non-blocking event file descriptor of a GPIOD_IO_BOTH_EDGES line (-1 for other modes). */
extern int gpiod_io_event_fd(const struct gpiod_io_line *line);

/**
 * Read up to max pending edge events from an event file descriptor without blocking.
 * The descriptor delivers the kernel's struct gpioevent_data records (what gpiod_io_event_fd() returns, or a
 * pipe a test writes such records into).
 * @return the number of events read (0 if none is pending), or -1 with errno set (EIO: a truncated record)
 */
extern int gpiod_io_read_edges(int fd, struct gpiod_io_edge *edges, unsigned max);

/** Release the line and its chip; NULL is a no-op. */
extern void gpiod_io_release(struct gpiod_io_line *line);

#endif /* GPIOD_IO_H */
