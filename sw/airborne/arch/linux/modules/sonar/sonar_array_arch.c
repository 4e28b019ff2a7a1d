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
 * @file arch/linux/modules/sonar/sonar_array_arch.c
 * The sonar ring's hardware on Linux (modules/sonar/sonar_array_arch.h): one trigger/echo sonar per ring
 * position on GPIO lines (modules/sonar/sonar_gpio.h), the speed of sound from the air temperature
 * (sonar_gpio_temperature.h).
 *
 * Wiring, per position NAME in FRONT, RIGHT, BACK, LEFT, DOWN (airframe defines):
 *   SONAR_GPIO_<NAME>_TRIGGER, SONAR_GPIO_<NAME>_ECHO   line offsets (-1: not fitted; it never reads)
 *   SONAR_GPIO_<NAME>_CHIP                              its gpiochip (default SONAR_GPIO_CHIP, "gpiochip0")
 * Echo timing: SONAR_GPIO_MIN_RANGE / SONAR_GPIO_MAX_RANGE [m] (what the driver calls valid),
 * SONAR_GPIO_TIMEOUT [us], SONAR_GPIO_MIN_PULSE [us] (glitch), SONAR_GPIO_BOUNCE [us].
 * A reading is the echo distance [m] (out-of-range distances included: the ring clamps them), or NAN for no
 * echo, a rejected echo, or a cycle not complete at read time.
 */

#include "modules/sonar/sonar_array_arch.h"
#include "modules/sonar/sonar_array_schedule.h"
#include "modules/sonar/sonar_gpio.h"
#include "modules/sonar/sonar_gpio_temperature.h"
#include "modules/multi_vehicle/vehicle_local.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/** Default gpiochip of every sonar line */
#ifndef SONAR_GPIO_CHIP
#define SONAR_GPIO_CHIP "gpiochip0"
#endif
/** Shortest / longest valid distance [m] (HC-SR04 datasheet: 2 cm to 4 m) */
#ifndef SONAR_GPIO_MIN_RANGE
#define SONAR_GPIO_MIN_RANGE 0.02f
#endif
#ifndef SONAR_GPIO_MAX_RANGE
#define SONAR_GPIO_MAX_RANGE 4.0f
#endif
/** No complete echo this long after the trigger: no echo [us] (4 m takes 24.1 ms at 0 deg C; HC-SR04 clones
 *  hold the echo high 38 ms or longer when nothing answers) */
#ifndef SONAR_GPIO_TIMEOUT
#define SONAR_GPIO_TIMEOUT 30000
#endif
/** A shorter high pulse is a glitch [us] (the shortest real echo, 2 cm, lasts 117 us) */
#ifndef SONAR_GPIO_MIN_PULSE
#define SONAR_GPIO_MIN_PULSE 50
#endif
/** A rise this soon after a glitch is contact bounce [us] */
#ifndef SONAR_GPIO_BOUNCE
#define SONAR_GPIO_BOUNCE 20
#endif

#define SONAR_GPIO_WIRING(_name) \
  { SONAR_GPIO_##_name##_CHIP, SONAR_GPIO_##_name##_TRIGGER, SONAR_GPIO_##_name##_ECHO }

#ifndef SONAR_GPIO_FRONT_CHIP
#define SONAR_GPIO_FRONT_CHIP SONAR_GPIO_CHIP
#endif
#ifndef SONAR_GPIO_FRONT_TRIGGER
#define SONAR_GPIO_FRONT_TRIGGER -1
#endif
#ifndef SONAR_GPIO_FRONT_ECHO
#define SONAR_GPIO_FRONT_ECHO -1
#endif
#ifndef SONAR_GPIO_RIGHT_CHIP
#define SONAR_GPIO_RIGHT_CHIP SONAR_GPIO_CHIP
#endif
#ifndef SONAR_GPIO_RIGHT_TRIGGER
#define SONAR_GPIO_RIGHT_TRIGGER -1
#endif
#ifndef SONAR_GPIO_RIGHT_ECHO
#define SONAR_GPIO_RIGHT_ECHO -1
#endif
#ifndef SONAR_GPIO_BACK_CHIP
#define SONAR_GPIO_BACK_CHIP SONAR_GPIO_CHIP
#endif
#ifndef SONAR_GPIO_BACK_TRIGGER
#define SONAR_GPIO_BACK_TRIGGER -1
#endif
#ifndef SONAR_GPIO_BACK_ECHO
#define SONAR_GPIO_BACK_ECHO -1
#endif
#ifndef SONAR_GPIO_LEFT_CHIP
#define SONAR_GPIO_LEFT_CHIP SONAR_GPIO_CHIP
#endif
#ifndef SONAR_GPIO_LEFT_TRIGGER
#define SONAR_GPIO_LEFT_TRIGGER -1
#endif
#ifndef SONAR_GPIO_LEFT_ECHO
#define SONAR_GPIO_LEFT_ECHO -1
#endif
#ifndef SONAR_GPIO_DOWN_CHIP
#define SONAR_GPIO_DOWN_CHIP SONAR_GPIO_CHIP
#endif
#ifndef SONAR_GPIO_DOWN_TRIGGER
#define SONAR_GPIO_DOWN_TRIGGER -1
#endif
#ifndef SONAR_GPIO_DOWN_ECHO
#define SONAR_GPIO_DOWN_ECHO -1
#endif

struct sonar_gpio_wiring {
  const char *chip;
  int trigger;  ///< line offset, -1 if not fitted
  int echo;     ///< line offset, -1 if not fitted
};

static const struct sonar_gpio_wiring sonar_gpio_wiring[SONAR_ARRAY_NB] = {
  [SONAR_ARRAY_FRONT] = SONAR_GPIO_WIRING(FRONT),
  [SONAR_ARRAY_RIGHT] = SONAR_GPIO_WIRING(RIGHT),
  [SONAR_ARRAY_BACK] = SONAR_GPIO_WIRING(BACK),
  [SONAR_ARRAY_LEFT] = SONAR_GPIO_WIRING(LEFT),
  [SONAR_ARRAY_DOWN] = SONAR_GPIO_WIRING(DOWN),
};
static const char *const sonar_gpio_name[SONAR_ARRAY_NB] = { "front", "right", "back", "left", "down" };

struct sonar_array_linux {
  struct sonar_gpio *sonar[SONAR_ARRAY_NB];  ///< NULL: not fitted
  bool trigger_failed[SONAR_ARRAY_NB];       ///< a trigger failure was reported
};

VEHICLE_LOCAL_DEFINE(struct sonar_array_linux, sonar_array_linux);

static void close_all(struct sonar_array_linux *sl)
{
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    sonar_gpio_close(sl->sonar[i]);
    sl->sonar[i] = NULL;
  }
}

bool sonar_array_arch_init(void)
{
  struct sonar_array_linux *sl = VEHICLE_LOCAL(sonar_array_linux);
  if (!sonar_gpio_temperature_init()) {
    fprintf(stderr, "sonar_array: SONAR_GPIO_TEMPERATURE %g deg C is outside [%g, %g]\n",
            (double)SONAR_GPIO_TEMPERATURE, (double)SONAR_ECHO_TEMP_MIN_C, (double)SONAR_ECHO_TEMP_MAX_C);
    return false;
  }
  unsigned fitted = 0;
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    const struct sonar_gpio_wiring *w = &sonar_gpio_wiring[i];
    if (w->trigger < 0 || w->echo < 0) {
      continue;
    }
    const struct sonar_gpio_config cfg = {
      .trigger_chip = w->chip, .trigger_line = (unsigned)w->trigger,
      .echo_chip = w->chip, .echo_line = (unsigned)w->echo,
      .consumer = "sonar_array",
      .echo = {
        .min_range_m = SONAR_GPIO_MIN_RANGE, .max_range_m = SONAR_GPIO_MAX_RANGE, .timeout_us = SONAR_GPIO_TIMEOUT,
        .min_pulse_us = SONAR_GPIO_MIN_PULSE, .bounce_us = SONAR_GPIO_BOUNCE,
      },
    };
    char err[256];
    sl->sonar[i] = sonar_gpio_open(&cfg, err, sizeof(err));
    if (sl->sonar[i] == NULL) {
      fprintf(stderr, "sonar_array: %s sonar: %s\n", sonar_gpio_name[i], err);
      close_all(sl);
      return false;
    }
    fitted++;
  }
  if (fitted == 0) {
    fprintf(stderr, "sonar_array: no sonar wired (define SONAR_GPIO_<FRONT|RIGHT|BACK|LEFT|DOWN>_TRIGGER and "
            "_ECHO, the line offsets)\n");
    return false;
  }
  return true;
}

void sonar_array_arch_trigger(uint8_t sonar, uint32_t now_us)
{
  struct sonar_array_linux *sl = VEHICLE_LOCAL(sonar_array_linux);
  if (sonar >= SONAR_ARRAY_NB || sl->sonar[sonar] == NULL) {
    return;
  }
  if (sonar_gpio_trigger(sl->sonar[sonar], now_us) < 0) {
    if (!sl->trigger_failed[sonar]) {
      sl->trigger_failed[sonar] = true;
      fprintf(stderr, "sonar_array: %s sonar: trigger failed: %s\n", sonar_gpio_name[sonar], strerror(errno));
    }
    return;
  }
  sl->trigger_failed[sonar] = false;
}

float sonar_array_arch_read(uint8_t sonar, uint32_t fired_us __attribute__((unused)), uint32_t now_us)
{
  struct sonar_array_linux *sl = VEHICLE_LOCAL(sonar_array_linux);
  if (sonar >= SONAR_ARRAY_NB || sl->sonar[sonar] == NULL) {
    return NAN;
  }
  struct sonar_echo_reading r;
  if (sonar_gpio_poll(sl->sonar[sonar], now_us, sonar_gpio_temperature_c(), &r) != 1) {
    return NAN;
  }
  if (r.status == SONAR_ECHO_REJECTED || isinf(r.distance_m)) {
    return NAN;
  }
  return r.distance_m;
}
