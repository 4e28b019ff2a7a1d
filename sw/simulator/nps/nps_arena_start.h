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
 * @file nps_arena_start.h
 * Where the copters of a swarm start: the same places in our host and in Paparazzi's NPS (finken_world).
 */

#ifndef NPS_ARENA_START_H
#define NPS_ARENA_START_H

#include "nps_arena.h"

#ifdef __cplusplus
extern "C" {
#endif

#ifndef NPS_START_CIRCLE_MAX
#define NPS_START_CIRCLE_MAX 8        ///< up to this many copters start on a circle, more on a grid
#endif
#ifndef NPS_START_RADIUS
#define NPS_START_RADIUS 1.0          ///< [m] copters start evenly spaced on a circle around the arena centre
#endif

/**
 * Start pose of copter v of n (position [m], yaw [rad]): up to NPS_START_CIRCLE_MAX copters evenly spaced on a circle
 * of NPS_START_RADIUS (less to stay clear of the walls) around the arena centre, facing outward (the SwarmLab
 * take-off); more copters one per cell of a grid of equal cells over the arena's bounding box, facing east, so that a
 * large swarm starts as dense as the arena makes it.
 */
extern void nps_arena_start_pose(const struct nps_arena *a, unsigned v, unsigned n, double pos_m[2], double *yaw_rad);

#ifdef __cplusplus
}
#endif

#endif /* NPS_ARENA_START_H */
