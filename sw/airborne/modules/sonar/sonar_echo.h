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
 * @file modules/sonar/sonar_echo.h
 * Trigger/echo ultrasonic ranging (HC-SR04 style) as pure logic: edges in, distance out.
 *
 * After a trigger the sensor raises its echo line for as long as the sound takes to reach the obstacle and
 * come back, so distance = c * width / 2 with the speed of sound c = 331.3 + 0.606 * T m/s (T in deg C; the
 * first-order expansion of c = 331.3 * sqrt(1 + T / 273.15) around 0 deg C: within 0.25 % from -20 to +40 deg C,
 * 0.9 % at the 85 deg C limit).
 *
 * Two clocks, never mixed:
 *   - the edge clock: times of the echo edges (the kernel's GPIO event timestamps on Linux, a timer capture
 *     on a microcontroller); only differences of two edge times are used (the pulse width);
 *   - the poll clock: trigger_us and now_us (the autopilot's clock); only used for the timeout.
 * Both are uint32_t microseconds and may wrap (differences are taken modulo 2^32).
 *
 * One cycle: sonar_echo_arm() at the trigger, sonar_echo_edge() for each edge in the order they happened,
 * sonar_echo_poll() until it hands out the cycle's one reading. Edge rules:
 *   - a falling edge before any rise is spurious and ignored;
 *   - a high pulse shorter than min_pulse_us is a glitch; if the line rises again within bounce_us of the
 *     glitch's fall, the pulse keeps the first rise as its start (contact bounce), else the next rise starts it;
 *   - a second rise while high means a falling edge was lost: the cycle is REJECTED;
 *   - edges after the cycle completed, or while not armed, are late and ignored;
 *   - no complete pulse within timeout_us of the trigger: OUT_OF_RANGE (no echo, or a disconnected line).
 * A reading is handed out once; re-arming drops an unread one (counted as an overrun), so an old echo is never
 * reported as a new one.
 */

#ifndef SONAR_ECHO_H
#define SONAR_ECHO_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Trigger pulse width [us] (HC-SR04 datasheet: trigger high for at least 10 us) */
#define SONAR_ECHO_TRIGGER_PULSE_US 10
/** Speed of sound at 0 deg C [m/s] and its slope [m/s/K] (linearised dry-air value, see file comment) */
#define SONAR_ECHO_C0_MPS 331.3f
#define SONAR_ECHO_C_SLOPE_MPS_K 0.606f
/** Air temperatures the formula is used for [deg C]; a source outside this is a sensor fault */
#define SONAR_ECHO_TEMP_MIN_C (-40.0f)
#define SONAR_ECHO_TEMP_MAX_C 85.0f

struct sonar_echo_config {
  float min_range_m;     ///< shortest distance reported as VALID [m]
  float max_range_m;     ///< longest distance reported as VALID [m]
  uint32_t timeout_us;   ///< no complete echo this long after the trigger: OUT_OF_RANGE [us]
  uint32_t min_pulse_us; ///< a shorter high pulse is a glitch [us]
  uint32_t bounce_us;    ///< a rise this soon after a glitch continues the pulse [us]
};

enum sonar_echo_status {
  SONAR_ECHO_VALID = 0,     ///< distance_m within [min_range_m, max_range_m]
  SONAR_ECHO_OUT_OF_RANGE,  ///< distance_m outside the range, or INFINITY if no echo was timed
  SONAR_ECHO_REJECTED,      ///< inconsistent edges (a lost edge) or a temperature out of range: distance_m is NAN
};

struct sonar_echo_reading {
  enum sonar_echo_status status;
  float distance_m;      ///< see status [m]
  uint32_t width_us;     ///< echo pulse width, 0 if none was timed [us]
  uint32_t trigger_us;   ///< trigger time (poll clock) [us]
  uint32_t done_us;      ///< poll time at which the reading was handed out [us]
  float temperature_c;   ///< air temperature used for the speed of sound [deg C]
};

/** Counters since init (for telemetry and tests). */
struct sonar_echo_stats {
  uint32_t triggers;       ///< cycles armed
  uint32_t valid;          ///< readings VALID
  uint32_t out_of_range;   ///< readings OUT_OF_RANGE (including timeouts)
  uint32_t timeouts;       ///< cycles with no complete echo within timeout_us
  uint32_t rejected;       ///< readings REJECTED (lost edge or bad temperature)
  uint32_t glitches;       ///< high pulses shorter than min_pulse_us
  uint32_t spurious_edges; ///< falling edges without a rise
  uint32_t missing_edges;  ///< rises while already high (a falling edge was lost)
  uint32_t late_edges;     ///< edges after the cycle completed or while not armed
  uint32_t overruns;       ///< cycles re-armed before their reading was handed out
};

enum sonar_echo_phase {
  SONAR_ECHO_IDLE = 0,   ///< not armed, or the reading was handed out
  SONAR_ECHO_WAIT_RISE,  ///< armed, echo line low
  SONAR_ECHO_WAIT_FALL,  ///< echo line high since rise_us
  SONAR_ECHO_DONE,       ///< cycle complete, reading not yet handed out
};

struct sonar_echo {
  struct sonar_echo_config cfg;
  enum sonar_echo_phase phase;
  uint32_t trigger_us;     ///< poll clock
  uint32_t rise_us;        ///< edge clock: start of the pulse
  uint32_t glitch_fall_us; ///< edge clock: fall of the last glitch
  bool glitch_pending;     ///< a glitch ended the last high pulse
  bool done_rejected;      ///< DONE because of a lost edge
  uint32_t width_us;       ///< DONE: the pulse width
  struct sonar_echo_stats stats;
};

/**
 * Check a configuration: 0 if usable, else -1 with *why naming the field and what was expected.
 * The timeout must cover the echo of max_range_m at 0 deg C.
 */
extern int sonar_echo_config_check(const struct sonar_echo_config *cfg, const char **why);

/** Start with cfg (checked by the caller with sonar_echo_config_check()). */
extern void sonar_echo_init(struct sonar_echo *se, const struct sonar_echo_config *cfg);

/** A trigger was sent at trigger_us (poll clock). Returns true if an unfinished or unread cycle was dropped. */
extern bool sonar_echo_arm(struct sonar_echo *se, uint32_t trigger_us);

/** An echo edge at edge_us (edge clock), in the order they happened. */
extern void sonar_echo_edge(struct sonar_echo *se, bool rising, uint32_t edge_us);

/**
 * Hand out the cycle's reading if it is complete or timed out at now_us (poll clock).
 * @param temperature_c air temperature [deg C] for the speed of sound; outside [SONAR_ECHO_TEMP_MIN_C,
 *        SONAR_ECHO_TEMP_MAX_C] (or NAN) the reading is REJECTED
 * @return true and *out filled once per cycle, false while the cycle is pending or after it was handed out
 */
extern bool sonar_echo_poll(struct sonar_echo *se, uint32_t now_us, float temperature_c,
                            struct sonar_echo_reading *out);

/** Speed of sound in air at temperature_c [m/s]: 331.3 + 0.606 * T. */
extern float sonar_echo_speed_of_sound(float temperature_c);

/** Distance [m] of an echo of width_us at temperature_c: c * width / 2. */
extern float sonar_echo_distance_m(uint32_t width_us, float temperature_c);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_ECHO_H */
