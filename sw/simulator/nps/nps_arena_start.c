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
#include "nps_geometry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/** Accuracy of the search for the centre of the largest free circle [m]. */
#define START_CENTRE_TOL_M 1e-3

/** The arena with its corners, for the clearance of a point. */
struct free_space {
  const struct nps_arena *a;
  double (*corners)[2];
};

static double free_clearance(const void *ctx, const double p[2])
{
  const struct free_space *f = ctx;
  const struct nps_arena *a = f->a;
  double clear = nps_geometry_polygon_clearance((const double (*)[2])f->corners, a->num_walls, p);
  for (int k = 0; k < a->num_obstacles; k++) {
    clear = fmin(clear, nps_obstacle_signed_dist(&a->obstacles[k], p));
  }
  return clear;
}

static int free_space_make(struct free_space *f, const struct nps_arena *a)
{
  f->a = a;
  f->corners = malloc((size_t)a->num_walls * sizeof * f->corners);
  for (int i = 0; f->corners != NULL && i < a->num_walls; i++) {
    f->corners[i][0] = a->walls[i].a[0];
    f->corners[i][1] = a->walls[i].a[1];
  }
  return f->corners != NULL ? 0 : -1;
}

double nps_arena_start_clearance(const struct nps_arena *a, const double p[2])
{
  struct free_space f;
  const double clear = free_space_make(&f, a) == 0 ? free_clearance(&f, p) : NAN;
  free(f.corners);
  return clear;
}

/** Whether the arena is a convex polygon (every turn of the walls the same way) without obstacles. */
static int convex_and_empty(const struct nps_arena *a)
{
  int left = 0, right = 0;
  for (int i = 0; i < a->num_walls; i++) {
    const struct nps_wall *w = &a->walls[i], *next = &a->walls[(i + 1) % a->num_walls];
    const double turn = w->t[0] * next->t[1] - w->t[1] * next->t[0];
    left += turn > 0.;
    right += turn < 0.;
  }
  return a->num_obstacles == 0 && (left == 0 || right == 0);
}

/** The bounding box of the walls. */
static void bounding_box(const struct nps_arena *a, double lo[2], double hi[2])
{
  lo[0] = lo[1] = INFINITY;
  hi[0] = hi[1] = -INFINITY;
  for (int i = 0; i < a->num_walls; i++) {
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], a->walls[i].a[k]);
      hi[k] = fmax(hi[k], a->walls[i].a[k]);
    }
  }
}

/** Centre of the start circle and its clearance [m]. */
static void circle_centre(const struct free_space *f, double centre_m[2], double *clear_m)
{
  const struct nps_arena *a = f->a;
  if (convex_and_empty(a)) {   /* the mean of the corners; its clearance is the least distance to a wall's line */
    centre_m[0] = centre_m[1] = 0.0;
    for (int i = 0; i < a->num_walls; i++) {
      centre_m[0] += a->walls[i].a[0] / a->num_walls;
      centre_m[1] += a->walls[i].a[1] / a->num_walls;
    }
    *clear_m = INFINITY;
    for (int i = 0; i < a->num_walls; i++) {
      const struct nps_wall *w = &a->walls[i];
      *clear_m = fmin(*clear_m, (centre_m[0] - w->a[0]) * w->n[0] + (centre_m[1] - w->a[1]) * w->n[1]);
    }
    return;
  }
  double lo[2], hi[2];
  bounding_box(a, lo, hi);
  *clear_m = nps_geometry_max_clearance(lo, hi, free_clearance, f, START_CENTRE_TOL_M, INFINITY, centre_m);
}

/** The least gap a copter needs to a wall or an obstacle (to its centre), and between two copters' centres [m]. */
static double wall_need_m(const struct nps_arena *a)
{
  return a->copter_radius_m + NPS_START_MARGIN;
}

static double copter_need_m(const struct nps_arena *a)
{
  return 2.0 * a->copter_radius_m + NPS_START_MARGIN;
}

/**
 * n copters on a circle facing outward: radius half the centre's clearance, at most NPS_START_RADIUS, widened
 * where neighbours would stand closer than copter_need_m (chord 2 r sin(pi / n)). @return whether it fits
 */
static int on_circle(const struct free_space *f, unsigned n, double (*pos_m)[2], double *yaw_rad)
{
  const struct nps_arena *a = f->a;
  double centre_m[2], clear_m;
  circle_centre(f, centre_m, &clear_m);
  double radius_m = fmin(NPS_START_RADIUS, 0.5 * clear_m);
  if (n > 1) {
    radius_m = fmax(radius_m, copter_need_m(a) / (2.0 * sin(M_PI / n)));
  }
  for (unsigned v = 0; v < n; v++) {
    yaw_rad[v] = 2.0 * M_PI * v / n;
    pos_m[v][0] = centre_m[0] + radius_m * cos(yaw_rad[v]);
    pos_m[v][1] = centre_m[1] + radius_m * sin(yaw_rad[v]);
    if (free_clearance(f, pos_m[v]) < wall_need_m(a)) {
      return 0;
    }
  }
  return 1;
}

/**
 * n copters in the first free cells, row by row, of the coarsest grid over the bounding box with enough of them
 * (cells for m = n, n + 1, ... copters: cols = ceil(sqrt(m width / depth)), rows = ceil(m / cols)).
 * @return 0, or -1 with the reason in err
 */
static int on_grid(const struct free_space *f, unsigned n, double (*pos_m)[2], double *yaw_rad, char *err,
                   size_t err_len)
{
  const struct nps_arena *a = f->a;
  double lo[2], hi[2];
  bounding_box(a, lo, hi);
  const double width = hi[0] - lo[0], depth = hi[1] - lo[1];
  for (unsigned m = n;; m++) {
    const unsigned cols = (unsigned)ceil(sqrt(m * width / depth)), rows = (m + cols - 1) / cols;
    if (fmin(width / cols, depth / rows) < copter_need_m(a)) {
      snprintf(err, err_len, "arena \"%s\" is too small for %u copters: they do not fit %g m apart and %g m from "
               "every wall and obstacle (a copter's radius %g m and a margin of %g m)", a->name, n,
               copter_need_m(a), wall_need_m(a), a->copter_radius_m, (double)NPS_START_MARGIN);
      return -1;
    }
    unsigned placed = 0;
    for (unsigned cell = 0; cell < cols * rows && placed < n; cell++) {
      const double p[2] = { lo[0] + width * ((cell % cols) + 0.5) / cols, lo[1] + depth * ((cell / cols) + 0.5) / rows };
      if (free_clearance(f, p) >= wall_need_m(a)) {
        pos_m[placed][0] = p[0];
        pos_m[placed][1] = p[1];
        yaw_rad[placed++] = 0.0;
      }
    }
    if (placed == n) {
      return 0;
    }
  }
}

int nps_arena_start_poses(const struct nps_arena *a, unsigned n, double (*pos_m)[2], double *yaw_rad, char *err,
                          size_t err_len)
{
  struct free_space f;
  if (free_space_make(&f, a) != 0) {
    snprintf(err, err_len, "out of memory placing the copters");
    return -1;
  }
  const int rc = n <= NPS_START_CIRCLE_MAX && on_circle(&f, n, pos_m, yaw_rad) ? 0
                 : on_grid(&f, n, pos_m, yaw_rad, err, err_len);
  free(f.corners);
  return rc;
}
