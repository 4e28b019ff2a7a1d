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

static int visit_cell(void *ctx, int cell, double t_exit)
{
  struct cast *c = ctx;
  const struct nps_arena_grid *g = c->a->grid;
  for (int k = g->seg_start[cell]; k < g->seg_start[cell + 1]; k++) {
    test_segment(c, &c->a->segs[g->seg_items[k]]);
  }
  for (int k = g->body_start[cell]; k < g->body_start[cell + 1]; k++) {
    test_copter(c, &c->a->copters[g->body_items[k]]);
  }
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
      .d = { dir[0] / norm, dir[1] / norm, dir[2] / norm }, .skip_a = skip_a, .skip_b = skip_b, .hit = hit
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
