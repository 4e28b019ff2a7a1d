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
 * @file arch/linux/modules/sonar/sonar_gpio.c
 * Trigger/echo sonar on GPIO lines (see sonar_gpio.h): the seam, the trigger pulse, the event reads.
 */

#include "modules/sonar/sonar_gpio.h"
#include "modules/sonar/sonar_gpiod.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/** Edge events read per sonar_gpio_poll() at most (bounds the time spent in the main loop) */
#define SONAR_GPIO_MAX_EDGES_PER_POLL 64

struct sonar_gpio {
  struct sonar_gpio_io io;
  struct sonar_echo echo;
};

/** The libgpiod lines behind the seam of sonar_gpio_open(). */
struct sonar_gpio_lines {
  struct sonar_gpiod_line *trigger;
  struct sonar_gpiod_line *echo;
};

static int lines_set_trigger(void *ctx, int level)
{
  return sonar_gpiod_set(((struct sonar_gpio_lines *)ctx)->trigger, level);
}

static void lines_release(void *ctx)
{
  struct sonar_gpio_lines *l = ctx;
  sonar_gpiod_release(l->trigger);
  sonar_gpiod_release(l->echo);
  free(l);
}

struct sonar_gpio *sonar_gpio_open_io(const struct sonar_echo_config *echo, const struct sonar_gpio_io *io,
    char *err, size_t errlen)
{
  const char *why;
  if (sonar_echo_config_check(echo, &why) != 0) {
    snprintf(err, errlen, "sonar: bad configuration: %s", why);
    errno = EINVAL;
    return NULL;
  }
  if (io->echo_fd < 0 || io->set_trigger == NULL) {
    snprintf(err, errlen, "sonar: the seam needs an event descriptor and a trigger function");
    errno = EINVAL;
    return NULL;
  }
  struct sonar_gpio *s = calloc(1, sizeof(*s));
  if (s == NULL) {
    snprintf(err, errlen, "sonar: out of memory");
    return NULL;
  }
  s->io = *io;
  sonar_echo_init(&s->echo, echo);
  return s;
}

struct sonar_gpio *sonar_gpio_open(const struct sonar_gpio_config *cfg, char *err, size_t errlen)
{
  char detail[192];
  const char *why;
  if (sonar_echo_config_check(&cfg->echo, &why) != 0) {
    snprintf(err, errlen, "sonar: bad configuration: %s", why);
    errno = EINVAL;
    return NULL;
  }
  struct sonar_gpio_lines *l = calloc(1, sizeof(*l));
  if (l == NULL) {
    snprintf(err, errlen, "sonar: out of memory");
    return NULL;
  }
  l->trigger = sonar_gpiod_request(cfg->trigger_chip, cfg->trigger_line, SONAR_GPIOD_OUTPUT, 0, cfg->consumer,
                                   detail, sizeof(detail));
  if (l->trigger == NULL) {
    snprintf(err, errlen, "sonar trigger: %s", detail);
    goto fail;
  }
  l->echo = sonar_gpiod_request(cfg->echo_chip, cfg->echo_line, SONAR_GPIOD_BOTH_EDGES, 0, cfg->consumer,
                                detail, sizeof(detail));
  if (l->echo == NULL) {
    snprintf(err, errlen, "sonar echo: %s", detail);
    goto fail;
  }
  const struct sonar_gpio_io io = {
    .echo_fd = sonar_gpiod_event_fd(l->echo),
    .set_trigger = lines_set_trigger,
    .ctx = l,
    .release = lines_release,
  };
  struct sonar_gpio *s = sonar_gpio_open_io(&cfg->echo, &io, err, errlen);
  if (s == NULL) {
    goto fail;
  }
  return s;

fail: {
    const int saved = errno;
    lines_release(l);
    errno = saved;
  }
  return NULL;
}

/** Feed the pending edge events to the cycle; 0, or -1 with errno. */
static int read_edges(struct sonar_gpio *s)
{
  struct sonar_gpiod_edge edges[SONAR_GPIO_MAX_EDGES_PER_POLL];
  unsigned total = 0;
  while (total < SONAR_GPIO_MAX_EDGES_PER_POLL) {
    const int n = sonar_gpiod_read_edges(s->io.echo_fd, edges, SONAR_GPIO_MAX_EDGES_PER_POLL - total);
    if (n < 0) {
      return -1;
    }
    if (n == 0) {
      break;
    }
    for (int i = 0; i < n; i++) {
      sonar_echo_edge(&s->echo, edges[i].rising, (uint32_t)(edges[i].t_ns / 1000U));
    }
    total += (unsigned)n;
  }
  return 0;
}

/** Busy-wait until us microseconds have passed since start (CLOCK_MONOTONIC). */
static void wait_since(const struct timespec *start, long us)
{
  struct timespec now;
  do {
    if (clock_gettime(CLOCK_MONOTONIC, &now) != 0) {
      return;
    }
  } while ((int64_t)(now.tv_sec - start->tv_sec) * 1000000000LL + (now.tv_nsec - start->tv_nsec) < us * 1000LL);
}

int sonar_gpio_trigger(struct sonar_gpio *s, uint32_t now_us)
{
  if (read_edges(s) < 0) {
    return -1;
  }
  struct timespec high_since;  /* taken once the line is high: the pulse lasts at least the full 10 us */
  if (s->io.set_trigger(s->io.ctx, 1) < 0 || clock_gettime(CLOCK_MONOTONIC, &high_since) != 0) {
    const int saved = errno;
    s->io.set_trigger(s->io.ctx, 0);
    errno = saved;
    return -1;
  }
  sonar_echo_arm(&s->echo, now_us);
  wait_since(&high_since, SONAR_ECHO_TRIGGER_PULSE_US);
  if (s->io.set_trigger(s->io.ctx, 0) < 0) {
    const int saved = errno;
    s->io.set_trigger(s->io.ctx, 0);
    errno = saved;
    return -1;
  }
  return 0;
}

int sonar_gpio_poll(struct sonar_gpio *s, uint32_t now_us, float temperature_c, struct sonar_echo_reading *out)
{
  if (read_edges(s) < 0) {
    return -1;
  }
  return sonar_echo_poll(&s->echo, now_us, temperature_c, out) ? 1 : 0;
}

int sonar_gpio_fd(const struct sonar_gpio *s)
{
  return s->io.echo_fd;
}

void sonar_gpio_stats(const struct sonar_gpio *s, struct sonar_echo_stats *out)
{
  *out = s->echo.stats;
}

void sonar_gpio_close(struct sonar_gpio *s)
{
  if (s == NULL) {
    return;
  }
  if (s->io.release != NULL) {
    s->io.release(s->io.ctx);
  }
  free(s);
}
