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
 * @file arch/linux/modules/sonar/sonar_gpiod.c
 * The sonar driver's GPIO lines with libgpiod 1.x (see sonar_gpiod.h; written and tested with 1.6).
 */

#include <gpiod.h>

/*
 * libgpiod 2.x (Debian 13, Ubuntu 24.04 and later) removed the line API this file uses (struct gpiod_line,
 * gpiod_line_request_*, gpiod_line_event_*) in favour of line settings and requests. Its gpiod.h has no version
 * macro, but every libgpiod 1.x gpiod.h defines GPIOD_LINE_BULK_MAX_LINES and 2.x's does not (it declares
 * struct gpiod_line_settings instead). Refuse 2.x with one message instead of a page of compiler errors: the
 * rest of the file is only compiled for 1.x.
 */
#ifndef GPIOD_LINE_BULK_MAX_LINES
#error "sonar_array (ap): found libgpiod 2.x (its gpiod.h has no GPIOD_LINE_BULK_MAX_LINES); the sonar GPIO \
driver needs libgpiod 1.x (1.6: the libgpiod-dev of Debian 12 and Ubuntu 22.04). Install libgpiod 1.6 and put \
its include and library folders first on the compiler's search paths, or leave sonar_array out of the ap target."
#else

#include "modules/sonar/sonar_gpiod.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Events read per call of libgpiod's reader (its own batch size is 16) */
#define SONAR_GPIOD_EVENT_BATCH 16

struct sonar_gpiod_line {
  struct gpiod_chip *chip;
  struct gpiod_line *line;
  int event_fd;
};

/** Write "gpiochip 'chip' line N: what: errno text" to err; keeps errno. */
static void line_error(char *err, size_t errlen, const char *chip, unsigned offset, const char *what)
{
  const int saved = errno;
  if (err != NULL && errlen > 0) {
    snprintf(err, errlen, "gpiochip '%s' line %u: %s: %s", chip, offset, what, strerror(saved));
  }
  errno = saved;
}

struct sonar_gpiod_line *sonar_gpiod_request(const char *chip, unsigned offset, enum sonar_gpiod_mode mode,
    int initial, const char *consumer, char *err, size_t errlen)
{
  struct sonar_gpiod_line *l = calloc(1, sizeof(*l));
  if (l == NULL) {
    line_error(err, errlen, chip, offset, "out of memory");
    return NULL;
  }
  l->event_fd = -1;
  l->chip = gpiod_chip_open_lookup(chip);
  if (l->chip == NULL) {
    if (errno == 0) {
      errno = ENOENT;
    }
    line_error(err, errlen, chip, offset, "cannot open the chip");
    goto fail_free;
  }
  if (offset >= gpiod_chip_num_lines(l->chip)) {
    char what[64];
    snprintf(what, sizeof(what), "no such line (the chip has %u)", gpiod_chip_num_lines(l->chip));
    errno = EINVAL;
    line_error(err, errlen, chip, offset, what);
    goto fail_close;
  }
  l->line = gpiod_chip_get_line(l->chip, offset);
  if (l->line == NULL) {
    line_error(err, errlen, chip, offset, "cannot get the line");
    goto fail_close;
  }
  const int rc = mode == SONAR_GPIOD_OUTPUT ? gpiod_line_request_output(l->line, consumer, initial ? 1 : 0)
                                            : gpiod_line_request_both_edges_events(l->line, consumer);
  if (rc < 0) {
    char what[96];
    const int saved = errno;
    const char *holder = gpiod_line_consumer(l->line);
    snprintf(what, sizeof(what), "cannot request the line%s%s%s", holder ? " (held by '" : "", holder ? holder : "",
             holder ? "')" : "");
    errno = saved;
    line_error(err, errlen, chip, offset, what);
    goto fail_close;
  }
  if (mode == SONAR_GPIOD_BOTH_EDGES) {
    l->event_fd = gpiod_line_event_get_fd(l->line);
    const int flags = l->event_fd < 0 ? -1 : fcntl(l->event_fd, F_GETFL);
    if (flags < 0 || fcntl(l->event_fd, F_SETFL, flags | O_NONBLOCK) < 0) {
      line_error(err, errlen, chip, offset, "cannot make the event descriptor non-blocking");
      goto fail_release;
    }
  }
  return l;

fail_release:
  gpiod_line_release(l->line);
fail_close: {
    const int saved = errno;
    gpiod_chip_close(l->chip);
    errno = saved;
  }
fail_free:
  free(l);
  return NULL;
}

int sonar_gpiod_set(struct sonar_gpiod_line *line, int value)
{
  return gpiod_line_set_value(line->line, value ? 1 : 0);
}

int sonar_gpiod_event_fd(const struct sonar_gpiod_line *line)
{
  return line->event_fd;
}

int sonar_gpiod_read_edges(int fd, struct sonar_gpiod_edge *edges, unsigned max)
{
  struct gpiod_line_event ev[SONAR_GPIOD_EVENT_BATCH];
  const unsigned n_max = max < SONAR_GPIOD_EVENT_BATCH ? max : SONAR_GPIOD_EVENT_BATCH;
  if (n_max == 0) {
    return 0;
  }
  const int n = gpiod_line_event_read_fd_multiple(fd, ev, n_max);
  if (n < 0) {
    return (errno == EAGAIN || errno == EWOULDBLOCK) ? 0 : -1;
  }
  for (int i = 0; i < n; i++) {
    edges[i].t_ns = (uint64_t)ev[i].ts.tv_sec * 1000000000U + (uint64_t)ev[i].ts.tv_nsec;
    edges[i].rising = ev[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE;
  }
  return n;
}

void sonar_gpiod_release(struct sonar_gpiod_line *line)
{
  if (line == NULL) {
    return;
  }
  gpiod_line_release(line->line);
  gpiod_chip_close(line->chip);
  free(line);
}

#endif /* libgpiod 1.x */
