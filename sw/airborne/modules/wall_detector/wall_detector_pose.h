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
 * @file modules/wall_detector/wall_detector_pose.h
 * Where and when, for the wall detector: the copter's pose, elapsed times of wrapping microsecond clocks and yaw
 * changes.
 */

#ifndef WALL_DETECTOR_POSE_H
#define WALL_DETECTOR_POSE_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Where the copter is: position in a fixed local frame (only differences are used) and heading. */
struct wall_detector_pose {
  float x_m;      ///< position east [m]
  float y_m;      ///< position north [m]
  float yaw_rad;  ///< heading, clockwise from north (Paparazzi's psi) [rad]
};

/** The sine and cosine of a bearing, kept with the bearing they are of: a copter's heading seldom changes. */
struct wall_detector_bearing {
  bool known;          ///< sin_b and cos_b are of bearing_rad
  float bearing_rad;   ///< [rad]
  float sin_b, cos_b;  ///< sinf and cosf of it
};

/** Keep in b the sine and cosine of bearing_rad, computed again only when its bits differ from the kept bearing's
 * (-0 from +0 too), so they are bit for bit sinf and cosf of it. */
static inline void wall_detector_bearing_update(struct wall_detector_bearing *b, float bearing_rad)
{
  if (!b->known || memcmp(&b->bearing_rad, &bearing_rad, sizeof(bearing_rad)) != 0) {
    b->known = true;
    b->bearing_rad = bearing_rad;
    b->sin_b = sinf(bearing_rad);
    b->cos_b = cosf(bearing_rad);
  }
}

/** Signed time from `then_us` to `now_us` [s]; wrap-safe for uint32 microsecond clocks. */
static inline float wall_detector_elapsed_s(uint32_t now_us, uint32_t then_us)
{
  return (float)(int32_t)(now_us - then_us) * 1e-6f;
}

/** Time from `then_us` to `now_us` [s], 0 when `then_us` is later. */
static inline float wall_detector_elapsed_nonnegative_s(uint32_t now_us, uint32_t then_us)
{
  const float elapsed_s = wall_detector_elapsed_s(now_us, then_us);
  return elapsed_s > 0.f ? elapsed_s : 0.f;
}

/**
 * An angle wrapped into [-pi, pi] [rad]: remainderf(angle, 2 pi), exactly (a remainder is always exact). An angle
 * within half a turn is returned unchanged (the nearest multiple of the turn is 0, a tie going to the even 0). An
 * angle within one and a half turns (strictly: the nearest multiple is one turn, no tie) is angle -+ turn, and that
 * subtraction is exact (Sterbenz: |angle| between half a turn and two turns), so it is what remainderf returns;
 * its sign is the one remainderf gives a zero remainder, the angle's. Only farther angles call remainderf.
 */
static inline float wall_detector_wrap_pi(float angle_rad)
{
  const float turn_rad = 2.f * (float)M_PI;
  const float magnitude_rad = fabsf(angle_rad);
  if (magnitude_rad <= 0.5f * turn_rad) {
    return angle_rad;
  }
  const float less_one_turn_rad = magnitude_rad - turn_rad;  // exact for |angle| <= 2 turns
  if (magnitude_rad <= 2.f * turn_rad && fabsf(less_one_turn_rad) < 0.5f * turn_rad) {
    return angle_rad > 0.f ? less_one_turn_rad : -less_one_turn_rad;
  }
  return remainderf(angle_rad, turn_rad);
}

/** |a - b| wrapped into [0, pi] [rad]. */
static inline float wall_detector_yaw_change_rad(float a_rad, float b_rad)
{
  return fabsf(wall_detector_wrap_pi(a_rad - b_rad));
}

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_POSE_H */
