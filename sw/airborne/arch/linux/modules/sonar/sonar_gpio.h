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
 * @file arch/linux/modules/sonar/sonar_gpio.h
 * Trigger/echo ultrasonic sonar (HC-SR04 style) on Linux GPIO lines, through libgpiod.
 *
 * Wiring per sonar: a trigger line (output) and an echo line (input, both-edge events; an HC-SR04 echo is
 * 5 V: level-shift it to the board's 3.3 V). sonar_gpio_trigger() drains old events, arms the cycle and sends
 * the 10 us trigger pulse (the only wait, a busy one); sonar_gpio_poll() reads the events that arrived without
 * blocking and hands out the cycle's one reading once it is complete or timed out. The pulse width comes from
 * the kernel's edge time stamps (not from when the autopilot got around to reading them), the distance from
 * the pure logic in modules/sonar/sonar_echo.h (edge rules, glitch and bounce rejection, timeout).
 *
 * The seam: everything comes through struct sonar_gpio_io, an event descriptor delivering the kernel's GPIO
 * event records and a trigger function. sonar_gpio_open() builds it from libgpiod lines; tests give
 * sonar_gpio_open_io() a pipe they write event records into and a fake trigger.
 * Errors: NULL or -1 with errno set; sonar_gpio_open() also writes one message naming the chip, the line and
 * the errno text.
 */

#ifndef SONAR_GPIO_H
#define SONAR_GPIO_H

#include "modules/sonar/sonar_echo.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct sonar_gpio;

/** Wiring of one sonar. */
struct sonar_gpio_config {
  const char *trigger_chip;     ///< gpiochip of the trigger line (name, number, path or label)
  unsigned trigger_line;        ///< its line offset
  const char *echo_chip;        ///< gpiochip of the echo line
  unsigned echo_line;           ///< its line offset
  const char *consumer;         ///< label the lines get (gpioinfo shows it)
  struct sonar_echo_config echo;
};

/** The seam: where echo events come from and where the trigger goes. */
struct sonar_gpio_io {
  int echo_fd;                             ///< non-blocking descriptor of kernel GPIO event records
  int (*set_trigger)(void *ctx, int level); ///< drive the trigger line; -1 and errno on failure
  void *ctx;
  void (*release)(void *ctx);              ///< called by sonar_gpio_close() (NULL: nothing to release)
};

/**
 * Request the trigger and echo lines.
 * @param err receives one message on failure, e.g. "sonar echo: gpiochip 'gpiochip9' line 4: cannot open the
 *        chip: No such file or directory", or the configuration field that is wrong
 * @return the sonar, or NULL with errno set (EINVAL: bad configuration)
 */
extern struct sonar_gpio *sonar_gpio_open(const struct sonar_gpio_config *cfg, char *err, size_t errlen);

/** A sonar on the given seam (the descriptor is not closed by sonar_gpio_close(); io->release may). */
extern struct sonar_gpio *sonar_gpio_open_io(const struct sonar_echo_config *echo, const struct sonar_gpio_io *io,
    char *err, size_t errlen);

/**
 * Start a cycle at now_us (the caller's clock): drain the echo events of the last cycle, arm, pulse the
 * trigger for SONAR_ECHO_TRIGGER_PULSE_US. A cycle whose reading was not handed out is dropped (counted in
 * the stats as an overrun). Returns 0, or -1 with errno (the trigger line failed; nothing armed).
 */
extern int sonar_gpio_trigger(struct sonar_gpio *s, uint32_t now_us);

/**
 * Read the echo events that arrived, without blocking; hand out the reading once the cycle is complete or
 * timed out at now_us.
 * @param temperature_c air temperature for the speed of sound [deg C]
 * @return 1 a reading in *out, 0 none yet (or already handed out), -1 with errno (the event descriptor failed)
 */
extern int sonar_gpio_poll(struct sonar_gpio *s, uint32_t now_us, float temperature_c,
                           struct sonar_echo_reading *out);

/** The echo event descriptor (to poll() on it). */
extern int sonar_gpio_fd(const struct sonar_gpio *s);

/** Counters since open. */
extern void sonar_gpio_stats(const struct sonar_gpio *s, struct sonar_echo_stats *out);

/** Release the lines; NULL is a no-op. */
extern void sonar_gpio_close(struct sonar_gpio *s);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_GPIO_H */
