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
 * @file modules/sonar/sonar_echo.c
 * Trigger/echo ultrasonic ranging as pure logic (see sonar_echo.h for the edge rules and the two clocks).
 */

#include "modules/sonar/sonar_echo.h"

#include <math.h>

int sonar_echo_config_check(const struct sonar_echo_config *cfg, const char **why)
{
  if (!(cfg->min_range_m >= 0.0f)) {
    *why = "min_range_m must be >= 0 m";
    return -1;
  }
  if (!(cfg->max_range_m > cfg->min_range_m)) {
    *why = "max_range_m must be greater than min_range_m";
    return -1;
  }
  if (cfg->min_pulse_us == 0) {
    *why = "min_pulse_us must be > 0 us";
    return -1;
  }
  /* the echo of max_range_m must fit in the timeout even in cold air (0 deg C) */
  const float max_width_us = 2.0f * cfg->max_range_m / SONAR_ECHO_C0_MPS * 1e6f;
  if ((float)cfg->timeout_us < max_width_us) {
    *why = "timeout_us must be at least the echo width of max_range_m at 0 deg C (2 * max_range_m / 331.3 m/s)";
    return -1;
  }
  return 0;
}

void sonar_echo_init(struct sonar_echo *se, const struct sonar_echo_config *cfg)
{
  *se = (struct sonar_echo) { .cfg = *cfg, .phase = SONAR_ECHO_IDLE };
}

bool sonar_echo_arm(struct sonar_echo *se, uint32_t trigger_us)
{
  const bool dropped = se->phase != SONAR_ECHO_IDLE;
  if (dropped) {
    se->stats.overruns++;
  }
  se->stats.triggers++;
  se->phase = SONAR_ECHO_WAIT_RISE;
  se->trigger_us = trigger_us;
  se->glitch_pending = false;
  se->done_rejected = false;
  se->width_us = 0;
  return dropped;
}

void sonar_echo_edge(struct sonar_echo *se, bool rising, uint32_t edge_us)
{
  switch (se->phase) {
    case SONAR_ECHO_WAIT_RISE:
      if (!rising) {
        se->stats.spurious_edges++;
        return;
      }
      /* a rise soon after a glitch is contact bounce: the pulse started at the first rise */
      if (!(se->glitch_pending && edge_us - se->glitch_fall_us <= se->cfg.bounce_us)) {
        se->rise_us = edge_us;
      }
      se->glitch_pending = false;
      se->phase = SONAR_ECHO_WAIT_FALL;
      return;
    case SONAR_ECHO_WAIT_FALL: {
      if (rising) {
        se->stats.missing_edges++;
        se->done_rejected = true;
        se->phase = SONAR_ECHO_DONE;
        return;
      }
      const uint32_t width_us = edge_us - se->rise_us;
      if (width_us < se->cfg.min_pulse_us) {
        se->stats.glitches++;
        se->glitch_pending = true;
        se->glitch_fall_us = edge_us;
        se->phase = SONAR_ECHO_WAIT_RISE;
        return;
      }
      se->width_us = width_us;
      se->phase = SONAR_ECHO_DONE;
      return;
    }
    case SONAR_ECHO_IDLE:
    case SONAR_ECHO_DONE:
    default:
      se->stats.late_edges++;
      return;
  }
}

float sonar_echo_speed_of_sound(float temperature_c)
{
  return SONAR_ECHO_C0_MPS + SONAR_ECHO_C_SLOPE_MPS_K * temperature_c;
}

float sonar_echo_distance_m(uint32_t width_us, float temperature_c)
{
  return sonar_echo_speed_of_sound(temperature_c) * ((float)width_us * 1e-6f) * 0.5f;
}

bool sonar_echo_poll(struct sonar_echo *se, uint32_t now_us, float temperature_c,
                     struct sonar_echo_reading *out)
{
  const bool pending = se->phase == SONAR_ECHO_WAIT_RISE || se->phase == SONAR_ECHO_WAIT_FALL;
  const bool timed_out = pending && now_us - se->trigger_us >= se->cfg.timeout_us;
  if (se->phase != SONAR_ECHO_DONE && !timed_out) {
    return false;
  }
  *out = (struct sonar_echo_reading) {
    .trigger_us = se->trigger_us,
    .done_us = now_us,
    .temperature_c = temperature_c,
  };
  if (timed_out) {
    se->stats.timeouts++;
    se->stats.out_of_range++;
    out->status = SONAR_ECHO_OUT_OF_RANGE;
    out->distance_m = INFINITY;
  } else if (se->done_rejected || !(temperature_c >= SONAR_ECHO_TEMP_MIN_C && temperature_c <= SONAR_ECHO_TEMP_MAX_C)) {
    se->stats.rejected++;
    out->status = SONAR_ECHO_REJECTED;
    out->distance_m = NAN;
  } else {
    out->width_us = se->width_us;
    out->distance_m = sonar_echo_distance_m(se->width_us, temperature_c);
    if (out->distance_m >= se->cfg.min_range_m && out->distance_m <= se->cfg.max_range_m) {
      se->stats.valid++;
      out->status = SONAR_ECHO_VALID;
    } else {
      se->stats.out_of_range++;
      out->status = SONAR_ECHO_OUT_OF_RANGE;
    }
  }
  se->phase = SONAR_ECHO_IDLE;
  return true;
}
