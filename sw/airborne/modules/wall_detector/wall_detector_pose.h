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

#ifdef __cplusplus
extern "C" {
#endif

/** Where the copter is: position in a fixed local frame (only differences are used) and heading. */
struct wall_detector_pose {
  float x_m;      ///< position east [m]
  float y_m;      ///< position north [m]
  float yaw_rad;  ///< heading, clockwise from north (Paparazzi's psi) [rad]
};

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

/** An angle wrapped into [-pi, pi] [rad] (an angle within half a turn unchanged). */
static inline float wall_detector_wrap_pi(float angle_rad)
{
  return remainderf(angle_rad, 2.f * (float)M_PI);
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
