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
 * @file nps_walls_step.c
 * One wall step over the arena: nearest copter per plate through the grid, PID targets and contact
 * limits, then the dynamics of every plate that is not at rest. A step costs in proportion to the copters
 * and the plates that move (nps_arena.active_segs), not to all the plates: a free plate at rest stays so.
 */

#include "nps_walls.h"
#include "nps_arena_grid.h"

#include <errno.h>
#include <math.h>

/** List plate i among the plates this step integrates (once). */
static void activate(struct nps_arena *a, int i)
{
  if (!a->segs[i].active) {
    a->segs[i].active = 1;
    a->active_segs[a->num_active++] = i;
  }
}

/**
 * Copter `copter`, at s along wall w and dp across it (dp2 = dp^2 < thr2, the threshold squared), updates the
 * wall's plates within the threshold: only plates overlapping [s - hw, s + hw], hw = sqrt(thr2 - dp2), can be that
 * close; the squared distance to plate k is dp^2 + (distance along the wall outside [lo_k, hi_k])^2.
 */
static void pull_plates(struct nps_arena *a, const struct nps_wall *w, int copter, double s, double dp2, double thr2)
{
  double hw = sqrt(thr2 - dp2);
  if (s + hw < 0. || s - hw > w->length_m) {
    return;
  }
  int n = w->p.num_segments;
  double seg_len = w->length_m / n;
  int k0 = s - hw <= 0. ? 0 : (int)((s - hw) / seg_len);
  int k1 = (int)((s + hw) / seg_len);
  k1 = k1 > n - 1 ? n - 1 : k1;
  for (int k = k0; k <= k1; k++) {
    double lo = k * seg_len, hi = k + 1 == n ? w->length_m : (k + 1) * seg_len;
    double e = s < lo ? lo - s : (s > hi ? s - hi : 0.);
    double d2 = dp2 + e * e;
    struct nps_wall_segment *seg = &a->segs[w->first_segment + k];
    if (d2 < thr2 && d2 < seg->nearest_m) {
      seg->nearest_m = d2;
      seg->nearest_copter = copter;
      activate(a, w->first_segment + k);
    }
  }
}

/**
 * Copter c, centred at p in cell `cell`, pulls the walls listed there (those within their threshold of the cell).
 * A listed wall is mostly farther than its threshold from the copter: that test comes first, inline.
 * @return the slack of this answer for g->wall_free (the least |dp| - threshold - margin over the walls; < 0 when
 * a wall is within its threshold) [m]
 */
static double pull_cell_walls(struct nps_arena *a, int c, const double p[2], int cell)
{
  const struct nps_arena_grid *g = a->grid;
  double slack_m = INFINITY;
  const int *item = g->wall_items + g->wall_start[cell], *end = g->wall_items + g->wall_start[cell + 1];
  for (; item < end; item++) {
    const struct nps_wall *w = &a->walls[*item];
    const double px = p[0] - w->a[0], py = p[1] - w->a[1];
    const double dp = px * w->n[0] + py * w->n[1];   /* across the wall, inward */
    const double thr2 = w->p.threshold_m * w->p.threshold_m;
    if (dp * dp < thr2) {
      pull_plates(a, w, c, px * w->t[0] + py * w->t[1], dp * dp, thr2);
    }
    /* margin: far above the rounding of dp, of |dx| + |dy| and of the squares (a few 1e-16 of these magnitudes) */
    const double margin_m = 1e-12 * (fabs(p[0]) + fabs(p[1]) + fabs(w->a[0]) + fabs(w->a[1]) + w->p.threshold_m);
    const double wall_slack_m = fabs(dp) - w->p.threshold_m - margin_m;
    slack_m = wall_slack_m < slack_m ? wall_slack_m : slack_m;
  }
  return slack_m;
}

/**
 * Each copter pulls the walls listed in its grid cell; a plate it gets near joins the active list. Only listed
 * plates can have a nearest copter from the last step.
 * A copter that found no listed wall within threshold skips the test while it stays in its cell and less than the
 * slack s from where it tested (|dx| + |dy| < s): the distance across a wall, (p - a) . n with |n| = 1, changes by
 * at most |n_x dx + n_y dy| <= |dx| + |dy|, so every wall stays beyond its threshold (the test would pull none).
 */
static void find_nearest(struct nps_arena *a)
{
  struct nps_arena_grid *g = a->grid;
  for (int j = 0; j < a->num_active; j++) {
    struct nps_wall_segment *s = &a->segs[a->active_segs[j]];
    s->nearest_m = INFINITY; /* squared until the end of this function */
    s->nearest_copter = -1;
  }
  for (int c = 0; c < a->num_copters; c++) {
    const double *p = a->copters[c].pos_m;
    const int cell = nps_arena_grid_indexed_cell(g, &a->copters[c], c);
    if (cell < 0 || g->wall_start[cell] == g->wall_start[cell + 1]) {
      continue;   /* outside the grid, or no wall within threshold of the cell */
    }
    struct nps_arena_grid_wall_free *f = &g->wall_free[c];
    if (cell == f->cell && fabs(p[0] - f->x_m) + fabs(p[1] - f->y_m) < f->slack_m) {
      continue;
    }
    *f = (struct nps_arena_grid_wall_free) { p[0], p[1], pull_cell_walls(a, c, p, cell), cell };
  }
}

/**
 * Contact limit of a driven plate for this step. atan is only needed when the plate can get there
 * within dt: it moves at most (|rate| + alpha_max dt) dt, and atan(x) >= x / (1 + x) for x >= 0.
 */
static double step_limit_rad(const struct nps_wall *w, const struct nps_wall_segment *s,
                             const struct nps_arena_copter *c, double distance_m, double dt)
{
  double below = w->p.hinge_height_m - (c->pos_m[2] - 0.5 * c->height_m);
  if (below <= 0.) {
    return M_PI / 2.;
  }
  double gap = distance_m - c->radius_m;
  double x = gap > 0. ? gap / below : 0.;
  double alpha_max = (w->p.joint_force_nm + w->restore_nm) / w->inertia_kgm2;
  double reach = s->angle_rad + (fabs(s->rate_rad_s) + alpha_max * dt) * dt;
  if (reach < x / (1. + x)) {
    return M_PI / 2.; /* out of reach this step */
  }
  return nps_walls_contact_limit_rad(distance_m, c->radius_m, c->pos_m[2] - 0.5 * c->height_m,
                                     w->p.hinge_height_m);
}

/** Targets, limit and dynamics of listed plate s; the plate has no nearest copter when none is within threshold. */
static void step_segment(struct nps_arena *a, struct nps_wall_segment *s, double dt)
{
  const struct nps_wall *w = &a->walls[s->wall];
  if (s->nearest_copter >= 0) {
    s->nearest_m = sqrt(s->nearest_m);
    if (!s->driven) {
      s->integral_deg_s = 0.;
    }
    s->driven = 1;
    s->target_deg = nps_walls_amplitude_deg(s->nearest_m, w->p.threshold_m, w->p.max_amplitude_deg);
    s->limit_rad = step_limit_rad(w, s, &a->copters[s->nearest_copter], s->nearest_m, dt);
  } else {
    s->driven = 0;
    s->target_deg = 0.;
    s->limit_rad = M_PI / 2.;
    if (s->angle_rad == 0. && s->rate_rad_s == 0.) {
      return; /* at rest and nobody near: nothing moves */
    }
  }
  nps_walls_segment_advance(w, s, dt);
}

/** On the first step, list the plates not at rest (a state given before the simulation starts). */
static void list_moving_plates(struct nps_arena *a)
{
  for (int i = 0; i < a->num_segments; i++) {
    if (a->segs[i].angle_rad != 0. || a->segs[i].rate_rad_s != 0.) {
      activate(a, i);
    }
  }
}

int nps_arena_walls_step(struct nps_arena *a, double time_s)
{
  if (!isfinite(time_s) || (a->stepped && time_s < a->time_s)) {
    errno = EINVAL;
    return -1;
  }
  if (!a->stepped) {
    list_moving_plates(a);
  }
  double dt = a->stepped ? time_s - a->time_s : 0.;
  a->time_s = time_s;
  a->stepped = 1;
  find_nearest(a);
  int kept = 0;
  for (int j = 0; j < a->num_active; j++) {
    const int i = a->active_segs[j];
    struct nps_wall_segment *s = &a->segs[i];
    step_segment(a, s, dt);
    if (!s->driven && s->angle_rad == 0. && s->rate_rad_s == 0.) {
      s->active = 0; /* free and at rest: it stays so until a copter comes near */
    } else {
      a->active_segs[kept++] = i;
    }
  }
  a->num_active = kept;
  return 0;
}

int nps_arena_walls_set_state(struct nps_arena *a, double time_s, const double *angle_rad, const double *rate_rad_s,
                              const double *integral_deg_s, int n)
{
  if (n != a->num_segments || !isfinite(time_s)) {
    errno = EINVAL;
    return -1;
  }
  for (int i = 0; i < n; i++) {
    struct nps_wall_segment *s = &a->segs[i];
    s->angle_rad = angle_rad[i];
    s->rate_rad_s = rate_rad_s[i];
    s->integral_deg_s = integral_deg_s[i];
    if (s->angle_rad != 0. || s->rate_rad_s != 0.) {
      activate(a, i);   /* a plate that moves is integrated by the next step */
    }
  }
  a->time_s = time_s;
  a->stepped = 1;
  return 0;
}
