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
 * Where the copters of a swarm start: the same places in our host and in Paparazzi's NPS (finken_world), inside the
 * free space of any simple polygon, clear of its walls, its obstacles and each other.
 */

#ifndef NPS_ARENA_START_H
#define NPS_ARENA_START_H

#include "nps_arena.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#ifndef NPS_START_CIRCLE_MAX
#define NPS_START_CIRCLE_MAX 8        ///< up to this many copters start on a circle (where it fits), more on a grid
#endif
#ifndef NPS_START_RADIUS
#define NPS_START_RADIUS 1.0          ///< [m] largest radius of the start circle
#endif
#ifndef NPS_START_MARGIN
#define NPS_START_MARGIN 0.1          ///< [m] least gap at the start between a copter's body and a wall, an obstacle
                                      ///< or another copter's body
#endif

/**
 * Start poses of the n copters of a swarm (position [m], yaw [rad]), copter v at pos_m[v] and yaw_rad[v].
 *
 * Up to NPS_START_CIRCLE_MAX copters stand evenly spaced on a circle, facing outward (the SwarmLab take-off), around
 * the centre of the free space: in a convex arena without obstacles the mean of its corners, otherwise the centre
 * of the largest circle clear of every wall and obstacle. The circle's radius is half the centre's clearance
 * (NPS_START_RADIUS at most), or more where the copters would stand closer than the margin allows. Where that
 * circle does not fit, and for more copters, they stand one per cell of a grid of equal cells over the arena's
 * bounding box, facing east, in the first free cells row by row (cells whose centre is clear of every wall and
 * obstacle), the grid as coarse as gives enough free cells: a large swarm starts as dense as the arena makes it.
 * Every copter is at least NPS_START_MARGIN from a wall, an obstacle and the other copters.
 *
 * @return 0, or -1 when the swarm does not fit, with the reason in err
 */
extern int nps_arena_start_poses(const struct nps_arena *a, unsigned n, double (*pos_m)[2], double *yaw_rad,
                                 char *err, size_t err_len);

/** Clearance of p [m]: distance to the nearest wall or obstacle, negative outside the arena or inside an obstacle. */
extern double nps_arena_start_clearance(const struct nps_arena *a, const double p[2]);

#ifdef __cplusplus
}
#endif

#endif /* NPS_ARENA_START_H */
