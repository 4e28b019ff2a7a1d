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
 * @file nps_arena_start.c
 * Where the copters of a swarm start (see nps_arena_start.h).
 */

#include "nps_arena_start.h"

#include <math.h>

/** Centre of the arena and the radius of the start circle: NPS_START_RADIUS, or less to stay clear of the walls. */
static void start_circle(const struct nps_arena *a, double centre_m[2], double *radius_m)
{
  centre_m[0] = centre_m[1] = 0.0;
  for (int i = 0; i < a->num_walls; i++) {
    centre_m[0] += a->walls[i].a[0] / a->num_walls;
    centre_m[1] += a->walls[i].a[1] / a->num_walls;
  }
  *radius_m = NPS_START_RADIUS;
  for (int i = 0; i < a->num_walls; i++) {
    const struct nps_wall *w = &a->walls[i];
    const double inside_m = (centre_m[0] - w->a[0]) * w->n[0] + (centre_m[1] - w->a[1]) * w->n[1];
    *radius_m = fmin(*radius_m, 0.5 * inside_m);
  }
}

void nps_arena_start_pose(const struct nps_arena *a, unsigned v, unsigned n, double pos_m[2], double *yaw_rad)
{
  if (n <= NPS_START_CIRCLE_MAX) {
    double centre_m[2], radius_m;
    start_circle(a, centre_m, &radius_m);
    *yaw_rad = 2.0 * M_PI * v / n;
    pos_m[0] = centre_m[0] + radius_m * cos(*yaw_rad);
    pos_m[1] = centre_m[1] + radius_m * sin(*yaw_rad);
    return;
  }
  double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
  for (int i = 0; i < a->num_walls; i++) {
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], a->walls[i].a[k]);
      hi[k] = fmax(hi[k], a->walls[i].a[k]);
    }
  }
  const double width = hi[0] - lo[0], depth = hi[1] - lo[1];
  const unsigned cols = (unsigned)ceil(sqrt(n * width / depth)), rows = (n + cols - 1) / cols;
  pos_m[0] = lo[0] + width * ((v % cols) + 0.5) / cols;
  pos_m[1] = lo[1] + depth * ((v / cols) + 0.5) / rows;
  *yaw_rad = 0.0;
}
