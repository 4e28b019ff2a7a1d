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
 * @file modules/sonar/sonar_array.h
 * The FINken sonar ring: four horizontal sonars (front, right, back, left) and one downward, fired in a
 * staggered round robin (sonar_array_schedule.h).
 *
 * Outputs on ABI: each horizontal reading as OBSTACLE_DETECTION (distance [m], elevation 0, heading [rad] in
 * the body frame: front 0, right pi/2, back pi, left -pi/2, as Paparazzi's range-finder arrays), the downward
 * one as AGL. The hardware (or its NPS simulation) sits behind sonar_array_arch.h.
 */

#ifndef SONAR_ARRAY_H
#define SONAR_ARRAY_H

#include "std.h"
#include "modules/sonar/sonar_array_schedule.h"
#include "modules/multi_vehicle/vehicle_local.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ABI sender ids (Paparazzi puts these in abi_sender_ids.h; override them there or in the airframe) */
#ifndef SONAR_ARRAY_FRONT_ID
#define SONAR_ARRAY_FRONT_ID 210
#endif
#ifndef SONAR_ARRAY_RIGHT_ID
#define SONAR_ARRAY_RIGHT_ID 211
#endif
#ifndef SONAR_ARRAY_BACK_ID
#define SONAR_ARRAY_BACK_ID 212
#endif
#ifndef SONAR_ARRAY_LEFT_ID
#define SONAR_ARRAY_LEFT_ID 213
#endif
#ifndef SONAR_ARRAY_DOWN_ID
#define SONAR_ARRAY_DOWN_ID 214
#endif

/** Readings per second of each sonar [Hz] (the ring fires SONAR_ARRAY_NB times as often) */
#ifndef SONAR_ARRAY_RATE
#define SONAR_ARRAY_RATE 20
#endif
/** Listening window of a sonar, in slots of the round robin (1 .. 4) */
#ifndef SONAR_ARRAY_READ_DELAY
#define SONAR_ARRAY_READ_DELAY 2
#endif
/** Shortest distance the sensor reports [m]; closer echoes read as this (report, section 3.2) */
#ifndef SONAR_ARRAY_MIN_RANGE
#define SONAR_ARRAY_MIN_RANGE 0.2f
#endif
/** Longest distance the sensor reports [m] (report, section 3.2) */
#ifndef SONAR_ARRAY_MAX_RANGE
#define SONAR_ARRAY_MAX_RANGE 3.0f
#endif
/** Without an echo within range: TRUE reports SONAR_ARRAY_MAX_RANGE, FALSE publishes nothing */
#ifndef SONAR_ARRAY_NO_ECHO_AS_MAX
#define SONAR_ARRAY_NO_ECHO_AS_MAX TRUE
#endif
/** Speed of sound for the window check [m/s] (dry air at 20 deg C) */
#ifndef SONAR_ARRAY_SPEED_OF_SOUND
#define SONAR_ARRAY_SPEED_OF_SOUND 343.0f
#endif

#if SONAR_ARRAY_RATE <= 0
#error "SONAR_ARRAY_RATE must be a positive number of readings per second"
#endif
#if SONAR_ARRAY_READ_DELAY < 1 || SONAR_ARRAY_READ_DELAY > 4  /* SONAR_ARRAY_NB - 1 (an enum: not usable in #if) */
#error "SONAR_ARRAY_READ_DELAY must be 1 to 4 slots"
#endif

struct sonar_array {
  struct sonar_array_schedule schedule;
  float distance_m[SONAR_ARRAY_NB];  ///< last published reading of each sonar [m]
  uint32_t stamp_us[SONAR_ARRAY_NB]; ///< when it was read [us]
  uint32_t count[SONAR_ARRAY_NB];    ///< readings published
  bool running;                      ///< false if the configuration was rejected at init
};

VEHICLE_LOCAL_DECLARE(struct sonar_array, sonar_array);

/** Heading of each sonar in the body frame [rad] (front 0, right pi/2, back pi, left -pi/2; down 0) */
extern const float sonar_array_heading_rad[SONAR_ARRAY_NB];
/** Elevation of each sonar [rad] (horizontal 0, down -pi/2) */
extern const float sonar_array_elevation_rad[SONAR_ARRAY_NB];

/**
 * What the ring publishes for a raw reading: the reading clamped to [min, max], or the maximum / nothing
 * (NAN) for "no echo" (raw NAN or beyond the maximum), per SONAR_ARRAY_NO_ECHO_AS_MAX.
 */
extern float sonar_array_reported_distance(float raw_m);

extern void sonar_array_init(void);
extern void sonar_array_periodic(void);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_ARRAY_H */
