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
 * @file nps_raycast.c
 * Ray casts against the deflected walls, the copter bodies and the floor, walking the arena grid
 * (see nps_raycast.h).
 */

#include "nps_raycast.h"
#include "nps_arena_grid.h"
#include "nps_geometry.h"

#include <math.h>

/** One ray cast in progress. */
struct cast {
  const struct nps_arena *a;
  double o[3], d[3];
  int skip_a, skip_b;
  struct nps_ray_hit *hit;     /* best so far; range_m is the search limit while kind is NOTHING */
  int prev_cell;               /* the cell visited before, -1 at the start: its walls are already tested */
};

static void set_point_normal(struct cast *c, double t, const double normal[3])
{
  struct nps_ray_hit *h = c->hit;
  double s = normal[0] * c->d[0] + normal[1] * c->d[1] + normal[2] * c->d[2] > 0. ? -1. : 1.;
  for (int k = 0; k < 3; k++) {
    h->point_m[k] = c->o[k] + t * c->d[k];
    h->normal[k] = s * normal[k];
  }
  h->range_m = t;
}

static int closer(const struct cast *c, double t)
{
  return t < c->hit->range_m || (c->hit->kind == NPS_HIT_NOTHING && t == c->hit->range_m);
}

static void take_wall(struct cast *c, double t, const double normal[3], const struct nps_wall_segment *s, int plate)
{
  set_point_normal(c, t, normal);
  c->hit->kind = NPS_HIT_WALL;
  c->hit->wall = s->wall;
  c->hit->segment = s->index;
  c->hit->plate = plate;
  c->hit->copter_id = -1;
}

/** Narrow [*t0, *t1] to where o + t d has its component along u (from origin point a) in [lo, hi]. */
static int slab(const double o[3], const double d[3], const double a[2], const double u[2], double lo, double hi,
                double *t0, double *t1)
{
  double q = (o[0] - a[0]) * u[0] + (o[1] - a[1]) * u[1];
  double dq = d[0] * u[0] + d[1] * u[1];
  if (dq == 0.) {
    return q >= lo && q <= hi;
  }
  double ta = (lo - q) / dq, tb = (hi - q) / dq;
  if (ta > tb) {
    double x = ta;
    ta = tb;
    tb = x;
  }
  *t0 = ta > *t0 ? ta : *t0;
  *t1 = tb < *t1 ? tb : *t1;
  return *t0 <= *t1;
}

/** The plate first (it wins ties with the sheet behind it), then the fixed curtain above and the sheet. */
static void test_segment(struct cast *c, const struct nps_wall_segment *s)
{
  const struct nps_wall *w = &c->a->walls[s->wall];
  double L = w->p.hinge_height_m, H = c->a->wall_height_m;
  /* quick rejection: the ray's ground track must cross the column's footprint, at most
   * L sin(angle) <= L min(angle, 1) inward of the rest line (tolerances as in nps_geometry_ray_rect) */
  const double tol = NPS_GEOMETRY_EDGE_TOL_M;
  double reach = L * (s->angle_rad < 1. ? s->angle_rad : 1.);
  double t0 = 0., t1 = c->hit->range_m;
  if (!slab(c->o, c->d, s->a, w->t, -tol, s->length_m + tol, &t0, &t1) ||
      !slab(c->o, c->d, s->a, w->n, -tol, reach + tol, &t0, &t1)) {
    return;
  }
  double sn = sin(s->angle_rad), cs = cos(s->angle_rad);
  struct nps_geometry_rect plate = {
    .corner = { s->a[0], s->a[1], L }, .e1 = { w->t[0], w->t[1], 0. }, .len1_m = s->length_m,
    .e2 = { sn * w->n[0], sn * w->n[1], -cs }, .len2_m = L, .normal = { cs * w->n[0], cs * w->n[1], sn }
  };
  double t = nps_geometry_ray_rect(c->o, c->d, &plate);
  if (closer(c, t)) {
    take_wall(c, t, plate.normal, s, 1);
  }
  struct nps_geometry_rect sheet = {
    .corner = { s->a[0], s->a[1], L }, .e1 = { w->t[0], w->t[1], 0. }, .len1_m = s->length_m,
    .e2 = { 0., 0., 1. }, .len2_m = H - L, .normal = { w->n[0], w->n[1], 0. }
  };
  if (H > L) {
    t = nps_geometry_ray_rect(c->o, c->d, &sheet);
    if (closer(c, t)) {
      take_wall(c, t, sheet.normal, s, 0);
    }
  }
  if (s->angle_rad > 0.) {
    sheet.corner[2] = 0.;
    sheet.len2_m = L;
    t = nps_geometry_ray_rect(c->o, c->d, &sheet);
    if (closer(c, t)) {
      take_wall(c, t, sheet.normal, s, 0);
    }
  }
}

static void test_copter(struct cast *c, const struct nps_arena_copter *q)
{
  if (q->id == c->skip_a || q->id == c->skip_b) {
    return;
  }
  double normal[3];
  double t = nps_geometry_ray_cylinder(c->o, c->d, q->pos_m, q->radius_m, 0.5 * q->height_m, normal);
  if (closer(c, t)) {
    set_point_normal(c, t, normal);
    c->hit->kind = NPS_HIT_COPTER;
    c->hit->copter_id = q->id;
    c->hit->wall = c->hit->segment = -1;
    c->hit->plate = 0;
  }
}

/** Index range [*k0, *k1] of the plates of w whose along-wall extent meets [s_lo, s_hi] (within tol). */
static int plates_along(const struct nps_wall *w, double s_lo, double s_hi, int *k0, int *k1)
{
  const double tol = NPS_GEOMETRY_EDGE_TOL_M, plate_m = w->length_m / w->p.num_segments;
  if (s_hi < -tol || s_lo > w->length_m + tol) {
    return 0;
  }
  /* plate k spans [k, k + 1] plate_m along the wall (nps_arena.c) */
  *k0 = s_lo - tol <= 0. ? 0 : (int)((s_lo - tol) / plate_m);
  *k1 = (int)((s_hi + tol) / plate_m);
  *k0 = *k0 < w->p.num_segments ? *k0 : w->p.num_segments - 1;
  *k1 = *k1 < w->p.num_segments ? *k1 : w->p.num_segments - 1;
  return 1;
}

/** Along-wall coordinate [m] of the ray's ground track at distance t. */
static double along(const struct cast *c, const struct nps_wall *w, double t)
{
  return (c->o[0] + t * c->d[0] - w->a[0]) * w->t[0] + (c->o[1] + t * c->d[1] - w->a[1]) * w->t[1];
}

/**
 * The plates of one wall the ray can meet, instead of every plate near its path: every surface of a wall
 * column lies within the band from its rest line to L inward (a plate reaches L sin(angle) <= L; the curtain
 * above and the sheet behind are on the rest line). A plate at rest can only be met where the ray's ground
 * track crosses the rest line; a deflected plate anywhere the track runs inside the band.
 */
static void test_wall(struct cast *c, int wall)
{
  const struct nps_wall *w = &c->a->walls[wall];
  const double tol = NPS_GEOMETRY_EDGE_TOL_M;
  double t0 = 0., t1 = c->hit->range_m;
  if (!slab(c->o, c->d, w->a, w->n, -tol, w->p.hinge_height_m + tol, &t0, &t1)) {
    return;
  }
  double r0 = t0, r1 = t1;
  int rest_k0 = 0, rest_k1 = -1, k0, k1;
  if (slab(c->o, c->d, w->a, w->n, -tol, tol, &r0, &r1)) {
    double s0 = along(c, w, r0), s1 = along(c, w, r1);
    if (!plates_along(w, fmin(s0, s1), fmax(s0, s1), &rest_k0, &rest_k1)) {
      rest_k1 = -1;
    }
  }
  double s0 = along(c, w, t0), s1 = along(c, w, t1);
  if (!plates_along(w, fmin(s0, s1), fmax(s0, s1), &k0, &k1)) {
    return;
  }
  for (int k = k0; k <= k1; k++) {
    const struct nps_wall_segment *s = &c->a->segs[w->first_segment + k];
    if (s->angle_rad > 0. || (k >= rest_k0 && k <= rest_k1)) {
      test_segment(c, s);
    }
  }
}

/** Whether wall is listed in cell (lists are sorted: index_boxes fills them in wall order). */
static int cell_lists_wall(const struct nps_arena_grid *g, int cell, int wall)
{
  for (int k = g->reach_start[cell]; k < g->reach_start[cell + 1] && g->reach_items[k] <= wall; k++) {
    if (g->reach_items[k] == wall) {
      return 1;
    }
  }
  return 0;
}

static int visit_cell(void *ctx, int cell, double t_exit)
{
  struct cast *c = ctx;
  const struct nps_arena_grid *g = c->a->grid;
  for (int k = g->reach_start[cell]; k < g->reach_start[cell + 1]; k++) {
    /* a wall's cells form a box, which a straight walk crosses in one run: a wall listed in the previous
     * cell was tested there, over the whole ray */
    if (c->prev_cell < 0 || !cell_lists_wall(g, c->prev_cell, g->reach_items[k])) {
      test_wall(c, g->reach_items[k]);
    }
  }
  for (int k = g->body_start[cell]; k < g->body_start[cell + 1]; k++) {
    test_copter(c, &c->a->copters[g->body_items[k]]);
  }
  c->prev_cell = cell;
  /* everything listed in later cells is hit beyond t_exit */
  return c->hit->kind != NPS_HIT_NOTHING && c->hit->range_m <= t_exit;
}

enum nps_hit_kind nps_raycast(const struct nps_arena *a, const double origin_m[3], const double dir[3],
                              double max_range_m, int skip_a, int skip_b, struct nps_ray_hit *hit)
{
  *hit = (struct nps_ray_hit) {
    .kind = NPS_HIT_NOTHING, .range_m = max_range_m, .wall = -1, .segment = -1, .copter_id = -1
  };
  double norm = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (norm > 0. && max_range_m >= 0.) {
    struct cast c = {
      .a = a, .o = { origin_m[0], origin_m[1], origin_m[2] },
      .d = { dir[0] / norm, dir[1] / norm, dir[2] / norm }, .skip_a = skip_a, .skip_b = skip_b, .hit = hit,
      .prev_cell = -1
    };
    if (c.d[2] < 0. && c.o[2] >= 0.) {
      double t = -c.o[2] / c.d[2];
      if (closer(&c, t)) {
        const double up[3] = { 0., 0., 1. };
        set_point_normal(&c, t, up);
        hit->kind = NPS_HIT_FLOOR;
      }
    }
    nps_arena_grid_walk(a->grid, c.o, c.d, hit->range_m, visit_cell, &c);
    for (int k = 0; k < a->grid->num_overflow; k++) {
      test_copter(&c, &a->copters[a->grid->overflow[k]]);
    }
  }
  if (hit->kind == NPS_HIT_NOTHING) {
    hit->range_m = INFINITY;
  }
  return hit->kind;
}

double nps_raycast_wall_dist(const struct nps_arena *a, const double p_m[3])
{
  double best2 = INFINITY;
  for (int i = 0; i < a->num_walls; i++) {
    best2 = fmin(best2, nps_geometry_point_segment_dist2(p_m, a->walls[i].a, a->walls[i].b));
  }
  return sqrt(best2);
}

int nps_raycast_line_blocked(const struct nps_arena *a, const double p_a[3], const double p_b[3],
                             int id_a, int id_b, struct nps_ray_hit *hit)
{
  struct nps_ray_hit local;
  struct nps_ray_hit *h = hit ? hit : &local;
  double d[3] = { p_b[0] - p_a[0], p_b[1] - p_a[1], p_b[2] - p_a[2] };
  double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return nps_raycast(a, p_a, d, len, id_a, id_b, h) != NPS_HIT_NOTHING;
}
