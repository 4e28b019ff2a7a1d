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
 * @file modules/finken_world/finken_world.h
 * The FINken arena inside Paparazzi's NPS: loads the arena, its curtain walls and the sensor model before any
 * sensor module starts, and gives the simulator this aircraft's pose from NPS's flight model (`fdm`) every step,
 * so that the NPS variants of sonar_array and virtual_ranging read the arena as they do in our host.
 *
 * Frames: the flight plan's origin is the arena's origin and its local NED frame the arena's (ENU: x east, y north,
 * z up), the same for every aircraft, so that Paparazzi's ground segment shows the swarm where it flies. Aircraft k
 * of a swarm of FINKEN_WORLD_AIRCRAFT starts where copter k - 1 starts in our host (nps_arena_start.h: on a circle
 * around the arena centre, facing outward): finken_world moves fdm_finken there before the first step. Then
 *   (x, y, z) = (east, north, -down),  yaw = pi/2 - psi
 * (psi: heading from north, clockwise seen from above; yaw: from the arena's x toward its y).
 */

#ifndef FINKEN_WORLD_H
#define FINKEN_WORLD_H

#include "std.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Arena pose of an aircraft from NPS's local NED pose (see the file comment). */
struct finken_world_pose {
  double pos_m[3];   ///< x east, y north, z up [m]
  double yaw_rad;    ///< from east toward north [rad]
  double speed_mps;  ///< horizontal speed [m/s]
};

/** The frame conversion above, pure: NED position [m], NED velocity [m/s], heading psi [rad]. */
extern struct finken_world_pose finken_world_pose_from_ned(const double ned_pos_m[3], const double ned_vel_mps[3],
    double psi_rad);

/**
 * The attitude of the pose rows (nps_run_log.h): the rotation from the body frame FLU (x forward, y left, z up) into
 * the arena frame ENU, as (qx, qy, qz, qw), from NPS's NED -> body FRD quaternion ned_quat = (qi, qx, qy, qz)
 * (fdm.ltpprz_to_body_quat): with the quaternion products written out (finken_world.c),
 *   (qw; qx, qy, qz) = (qi + qz; qx + qy, qx - qy, qi - qz) / sqrt(2).
 */
extern void finken_world_attitude_from_ned(const double ned_quat[4], double q_xyzw[4]);

extern void finken_world_init(void);
extern void finken_world_periodic(void);

#ifdef __cplusplus
}
#endif

#endif /* FINKEN_WORLD_H */
