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
 * @file nps_flight_truth.h
 * The ground truth of a reading from a lab's flight: a sonar's true range and the context of the range log
 * (ctx_target_copter, ctx_wall_dist, ctx_floor and the facing sonars) against the arena as drawn (walls at rest),
 * with the copters placed where the motion capture saw them (nps_arena_set_copters). The sonar's ray is given in
 * full (its mount and boresight turned by the copter's attitude, tools/finken/flight/truth.py), where the simulator
 * ignores roll and pitch (nps_raycast_sonar_pose). The same ray casts as the simulator's (nps_raycast.h).
 */

#ifndef NPS_FLIGHT_TRUTH_H
#define NPS_FLIGHT_TRUTH_H

#include "nps_raycast.h"

/** Facing sonars listed per reading, nearest first (as the simulator examines, nps_swarm_sonar.c). */
#define NPS_FLIGHT_TRUTH_MAX_FACING 8

/** Ray length for the ground truth, beyond any arena [m]: no hit reads as this (the simulator's convention). */
#define NPS_FLIGHT_TRUTH_RANGE_M 100.0

/** The truth of one sonar reading. */
struct nps_flight_sonar_truth {
  double true_range_m;     /**< first hit along the ray [m]; NPS_FLIGHT_TRUTH_RANGE_M when nothing is hit */
  int hit_kind;            /**< enum nps_hit_kind of that hit */
  double wall_dist_m;      /**< ctx_wall_dist: horizontal distance from the copter's centre to the nearest wall [m] */
  double floor;            /**< ctx_floor: floor material under the copter (nps_floor.h) */
  int facing;              /**< other copters' sonars facing this one with a clear path (may exceed the list) */
  int facing_copter[NPS_FLIGHT_TRUTH_MAX_FACING]; /**< their copter ids, nearest first */
  int facing_sonar[NPS_FLIGHT_TRUTH_MAX_FACING];  /**< which sonar of that copter (enum nps_sonar) */
  double facing_path_m[NPS_FLIGHT_TRUTH_MAX_FACING]; /**< one-way path from it [m] */
  int listed;              /**< entries filled in the lists (<= NPS_FLIGHT_TRUTH_MAX_FACING) */
};

/**
 * The truth of copter rx_id's sonar reading along origin_m + t dir (unit dir), the copters already in the arena.
 * Facing sonars: the other copters' sonars in whose beam cone this sonar lies, and it in theirs, at most the arena's
 * sonar range apart (nps_raycast_facing_nearest: their geometry is the simulator's, yaw only), with a clear path
 * (nps_raycast_line_blocked). Whether their pulses arrive while this sonar listens depends on when they fired, which
 * only the copters' records tell (the caller decides).
 * @return 0, or -1 when rx_id is not one of the arena's copters
 */
int nps_flight_truth_sonar(const struct nps_arena *a, int rx_id, const double origin_m[3], const double dir[3],
                           struct nps_flight_sonar_truth *out);

/** The arena's sonar geometry: the mount's distance from the copter centre along the boresight [m], the beam's
 * half-angle [rad] and range [m] (the arena file's <sonars>). */
void nps_flight_truth_sonar_geometry(const struct nps_arena *a, double *offset_m, double *half_angle_rad,
                                     double *range_m);

#endif /* NPS_FLIGHT_TRUTH_H */
