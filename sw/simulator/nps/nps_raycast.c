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
  double dh2;                  /* d[0]^2 + d[1]^2, the squared horizontal part of d (surely_misses) */
  int skip_a, skip_b;
  struct nps_ray_hit *hit;     /* best so far; range_m is the search limit while kind is NOTHING */
  int any;                     /* 1: any hit will do (a blocked line), not only the nearest */
  int geometry;                /* 1: the hit's point and normal are wanted (0: they stay zero) */
};

/** The hit's point at range t and its normal turned toward the side the ray came from. */
static void set_geometry(struct cast *c, double t, const double normal[3])
{
  struct nps_ray_hit *h = c->hit;
  double s = normal[0] * c->d[0] + normal[1] * c->d[1] + normal[2] * c->d[2] > 0. ? -1. : 1.;
  for (int k = 0; k < 3; k++) {
    h->point_m[k] = c->o[k] + t * c->d[k];
    h->normal[k] = s * normal[k];
  }
}

/** The hit's range t and, if wanted, its point and normal (inline: a range reading wants neither). */
static inline void set_point_normal(struct cast *c, double t, const double normal[3])
{
  c->hit->range_m = t;
  if (c->geometry) {
    set_geometry(c, t, normal);
  }
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
  c->hit->obstacle = -1;
}

/**
 * Whether a sheet spanning heights [z_lo, z_lo + height] surely misses a horizontal ray: nps_geometry_ray_rect
 * finds such a ray at height u = o_z - z_lo on the sheet (w_z = o_z + t 0 - z_lo, e2 = (0, 0, 1)), which must lie
 * in [-tol, height + tol]; the same operations here, so this never rejects a sheet ray_rect would hit.
 */
static int sheet_out_of_reach(const struct cast *c, double z_lo_m, double height_m)
{
  const double tol = NPS_GEOMETRY_EDGE_TOL_M, u = c->o[2] - z_lo_m;
  return c->d[2] == 0. && (u < -tol || u > height_m + tol);
}

/**
 * nps_geometry_ray_rect of a plate at rest (corner (a, L), e1 = (t, 0), e2 = (0 n, -1), normal (n, 0), sides the
 * segment's length and L) for a horizontal ray (d_z = 0), with its operations less those whose terms are zero:
 * denom = n . d_h (+ 0 d_z), t = (n . (a - o_h) + 0 (L - o_z)) / denom (the zero term kept: t is the same double,
 * even the sign of a zero t), then at o + t d the plate's height u = L - o_z (= -(o_z + t 0 - L), the same value)
 * and its along-wall s = (o_h + t d_h - a) . e1 within the edge tolerance. The zero terms left out of denom, u and
 * s can only change the sign of a zero result, which the comparisons ignore: the same t or INFINITY as the
 * general test (test_raycast checks it bit for bit).
 */
static double rest_plate_horizontal(const struct cast *c, const struct nps_wall_segment *s, const struct nps_wall *w,
                                    double hinge_m)
{
  const double tol = NPS_GEOMETRY_EDGE_TOL_M, u = hinge_m - c->o[2];
  const double denom = w->n[0] * c->d[0] + w->n[1] * c->d[1];
  if (denom == 0. || u < -tol || u > hinge_m + tol) {
    return INFINITY;
  }
  const double t = (w->n[0] * (s->a[0] - c->o[0]) + w->n[1] * (s->a[1] - c->o[1]) + 0. * (hinge_m - c->o[2])) / denom;
  if (!(t >= 0.)) {
    return INFINITY;
  }
  const double along_m = (c->o[0] + t * c->d[0] - s->a[0]) * w->t[0] + (c->o[1] + t * c->d[1] - s->a[1]) * w->t[1];
  return along_m < -tol || along_m > s->length_m + tol ? INFINITY : t;
}

/** The hinged plate of segment s against the ray: its range (INFINITY if missed) and its normal. */
static double test_plate(const struct cast *c, const struct nps_wall_segment *s, const struct nps_wall *w,
                         double normal[3])
{
  const double L = w->p.hinge_height_m;
  if (s->angle_rad == 0. && c->d[2] == 0.) {   /* the sonars' horizontal rays against a plate at rest */
    normal[0] = w->n[0];
    normal[1] = w->n[1];
    normal[2] = 0.;
    return rest_plate_horizontal(c, s, w, L);
  }
  /* a plate at rest needs no sine: sin 0 = 0 and cos 0 = 1 exactly */
  const double sn = s->angle_rad == 0. ? 0. : sin(s->angle_rad), cs = s->angle_rad == 0. ? 1. : cos(s->angle_rad);
  struct nps_geometry_rect plate = {
    .corner = { s->a[0], s->a[1], L }, .e1 = { w->t[0], w->t[1], 0. }, .len1_m = s->length_m,
    .e2 = { sn * w->n[0], sn * w->n[1], -cs }, .len2_m = L, .normal = { cs * w->n[0], cs * w->n[1], sn }
  };
  for (int k = 0; k < 3; k++) {
    normal[k] = plate.normal[k];
  }
  return nps_geometry_ray_rect(c->o, c->d, &plate);
}

/** The sheet on the rest line of segment s spanning heights [z_lo, z_lo + height] against the ray, if in reach. */
static void test_sheet(struct cast *c, const struct nps_wall_segment *s, const struct nps_wall *w, double z_lo_m,
                       double height_m)
{
  if (sheet_out_of_reach(c, z_lo_m, height_m)) {
    return;
  }
  const struct nps_geometry_rect sheet = {
    .corner = { s->a[0], s->a[1], z_lo_m }, .e1 = { w->t[0], w->t[1], 0. }, .len1_m = s->length_m,
    .e2 = { 0., 0., 1. }, .len2_m = height_m, .normal = { w->n[0], w->n[1], 0. }
  };
  const double t = nps_geometry_ray_rect(c->o, c->d, &sheet);
  if (closer(c, t)) {
    take_wall(c, t, sheet.normal, s, 0);
  }
}

/**
 * The plate first (it wins ties with the sheet behind it), then the fixed curtain above and the sheet: the exact
 * tests, no quick rejection of its own (test_wall_plates only passes plates whose band the ray's track crosses,
 * which nearly always get hit or missed only by the exact test).
 */
static void test_segment(struct cast *c, const struct nps_wall *w, const struct nps_wall_segment *s)
{
  const double L = w->p.hinge_height_m, H = c->a->wall_height_m;
  double normal[3];
  const double t = test_plate(c, s, w, normal);
  if (closer(c, t)) {
    take_wall(c, t, normal, s, 1);
  }
  if (H > L) {
    test_sheet(c, s, w, L, H - L);
  }
  if (s->angle_rad > 0.) {
    test_sheet(c, s, w, 0., L);
  }
}

/**
 * Cheap sufficient condition for the ray to miss copter q's body (a vertical cylinder): seen from above, the
 * line of the ray passes farther than the radius from the axis (|w x d_h|^2 > r^2 |d_h|^2, w the centre seen
 * from the origin, d_h the horizontal part of d), or the origin is outside the radius and the ray does not
 * approach the axis (w . d_h <= 0: its squared distance |w|^2 - 2 t w . d_h + t^2 |d_h|^2 never falls below |w|^2;
 * this covers a vertical ray, the down sonar's, d_h = 0); every point of the body, caps included, is within the
 * radius of the axis.
 * For a horizontal ray (the sonars), every point of the body is at t >= w . d - r: beyond the hit so far when
 * that exceeds its range. The radius is grown by a millionth so that rounding never rejects a body
 * nps_geometry_ray_cylinder hits (closer than the hit so far). Always inlined: it runs for every copter and ray.
 */
static inline __attribute__((always_inline)) int surely_misses(const struct cast *c, const struct nps_arena_copter *q)
{
  const double wx = q->pos_m[0] - c->o[0], wy = q->pos_m[1] - c->o[1];
  const double r = q->radius_m * (1. + 1e-6), cross = wx * c->d[1] - wy * c->d[0];
  const double along = wx * c->d[0] + wy * c->d[1];
  return cross * cross > r * r * c->dh2 || (along <= 0. && wx * wx + wy * wy > r * r) ||
         (c->d[2] == 0. && along - r > c->hit->range_m);
}

/** The exact test of copter q's body (test_copter's part past the quick rejection). */
static __attribute__((noinline)) void hit_copter(struct cast *c, const struct nps_arena_copter *q)
{
  double normal[3];
  const double half_height_m = 0.5 * q->height_m;
  const double t = c->geometry ? nps_geometry_ray_cylinder(c->o, c->d, q->pos_m, q->radius_m, half_height_m, normal)
                   : nps_geometry_ray_cylinder_range(c->o, c->d, q->pos_m, q->radius_m, half_height_m);
  if (closer(c, t)) {
    set_point_normal(c, t, normal);
    c->hit->kind = NPS_HIT_COPTER;
    c->hit->copter_id = q->id;
    c->hit->wall = c->hit->segment = c->hit->obstacle = -1;
    c->hit->plate = 0;
  }
}

/** Copter q's body against the ray, unless skipped or surely missed (kept small: it is inlined in the loops). */
static inline void test_copter(struct cast *c, const struct nps_arena_copter *q)
{
  if (q->id != c->skip_a && q->id != c->skip_b && !surely_misses(c, q)) {
    hit_copter(c, q);
  }
}

/**
 * Widening [m] of the bands and plate ranges by which test_wall picks the plates for test_segment: far more
 * than the rounding of these coordinates, so no plate test_segment would accept (to NPS_GEOMETRY_EDGE_TOL_M)
 * is skipped. test_wall is only a filter; test_segment decides.
 */
#define WALL_FILTER_TOL_M 1e-6

/** The ray's ground track in a wall's frame: along-wall s = s_o + t ds and inward n = n_o + t dn [m]. */
struct track {
  double s_o, ds, n_o, dn;
  double per_dn;   /**< 1 / dn */
};

/**
 * The track of the ray in the frame of w, given its inward part n_o = (o - a) . n, dn = d . n (test_wall's, kept
 * in registers: the quick rejection needs no more).
 */
static struct track wall_track(const struct cast *c, const struct nps_wall *w, double n_o, double dn)
{
  const double x = c->o[0] - w->a[0], y = c->o[1] - w->a[1];
  const struct track tr = {
    .s_o = x * w->t[0] + y * w->t[1], .ds = c->d[0] * w->t[0] + c->d[1] * w->t[1], .n_o = n_o, .dn = dn,
    .per_dn = 1. / dn
  };
  return tr;
}

/**
 * Quick rejection without a division: the track's inward n = n_o + t dn stays outside [lo, hi] for t in
 * [0, t_max] (it starts beyond one side and moves away, or gets there only after t_max: |n_o - edge| > |dn| t_max).
 * The margin (a relative 1e-9) is far above the rounding of track_band's quotient, so track_band would reject
 * every track this rejects.
 */
static int never_in_band(double n_o, double dn, double lo, double hi, double t_max)
{
  /* the reach only for a track moving toward the band (the far walls' case; the others need two comparisons) */
  if (n_o > hi) {
    return dn >= 0. || n_o - hi > -dn * t_max * (1. + 1e-9) + 1e-12;
  }
  if (n_o < lo) {
    return dn <= 0. || lo - n_o > dn * t_max * (1. + 1e-9) + 1e-12;
  }
  return 0;
}

/** Narrow [*t0, *t1] to where the track's inward n lies in [lo, hi]; 0 if nothing is left. Inlined (as
 * track_plates): test_wall_plates calls each twice per wall and once per deflected plate, its locals in registers. */
static inline __attribute__((always_inline)) int track_band(const struct track *tr, double lo, double hi, double *t0,
                                                            double *t1)
{
  if (tr->dn == 0.) {
    return tr->n_o >= lo && tr->n_o <= hi;
  }
  const double ta = (lo - tr->n_o) * tr->per_dn, tb = (hi - tr->n_o) * tr->per_dn;
  const double t_in = ta < tb ? ta : tb, t_out = ta < tb ? tb : ta;
  *t0 = t_in > *t0 ? t_in : *t0;
  *t1 = t_out < *t1 ? t_out : *t1;
  return *t0 <= *t1;
}

/** Index range [*k0, *k1] of the plates of w the track meets between t0 and t1 (widened); 0 if none. */
static inline __attribute__((always_inline)) int track_plates(const struct nps_wall *w, const struct track *tr,
                                                              double t0, double t1, int *k0, int *k1)
{
  const double tol = WALL_FILTER_TOL_M, per_m = w->plates_per_m;
  const double s0 = tr->s_o + t0 * tr->ds, s1 = tr->s_o + t1 * tr->ds;
  const double lo = (s0 < s1 ? s0 : s1) - tol, hi = (s0 < s1 ? s1 : s0) + tol;
  if (!(hi >= 0. && lo <= w->length_m)) {
    return 0;
  }
  /* plate k spans [k, k + 1] length / num_segments along the wall (nps_arena.c) */
  const double last = w->p.num_segments - 1;
  const double f0 = lo * per_m, f1 = hi * per_m;
  *k0 = f0 <= 0. ? 0 : (int)(f0 < last ? f0 : last);
  *k1 = (int)(f1 < last ? f1 : last);
  return 1;
}

/**
 * Whether the track meets deflected plate k of w where the plate can be: between t0 and t1, within the plate's
 * inward reach L min(angle, 1) >= L sin(angle) (as in test_segment; the sheets behind and above are on the rest
 * line) along its span. Widened as the bands; only a filter, test_segment decides.
 */
static int deflected_plate_in_reach(const struct nps_wall *w, const struct track *tr, double t0, double t1, int k,
                                    double angle_rad)
{
  const double tol = WALL_FILTER_TOL_M, reach_m = w->p.hinge_height_m * (angle_rad < 1. ? angle_rad : 1.);
  int k0, k1;
  return track_band(tr, -tol, reach_m + tol, &t0, &t1) && track_plates(w, tr, t0, t1, &k0, &k1) && k >= k0 && k <= k1;
}

/**
 * The plates of one wall the ray can meet, instead of every plate near its path: every surface of a wall
 * column lies within the band from its rest line to L inward (a plate reaches L sin(angle) <= L; the curtain
 * above and the sheet behind are on the rest line). A plate at rest can only be met where the ray's ground
 * track crosses the rest line; a deflected plate (rare in a small swarm, many in a large one, each exact test
 * with a sine and a cosine) only where the track runs within its own reach. The plates go to test_segment in
 * order along the wall (the first of two equal hits wins).
 */
static __attribute__((noinline)) void test_wall_plates(struct cast *c, const struct nps_wall *w, double n_o, double dn)
{
  const double tol = WALL_FILTER_TOL_M;
  const struct track tr = wall_track(c, w, n_o, dn);
  double t0 = 0., t1 = c->hit->range_m;
  int k0, k1;
  if (!track_band(&tr, -tol, w->p.hinge_height_m + tol, &t0, &t1) || !track_plates(w, &tr, t0, t1, &k0, &k1)) {
    return;
  }
  double r0 = t0, r1 = t1;
  int rest_k0 = 0, rest_k1 = -1;
  if (!track_band(&tr, -tol, tol, &r0, &r1) || !track_plates(w, &tr, r0, r1, &rest_k0, &rest_k1)) {
    rest_k1 = -1;
  }
  for (int k = k0; k <= k1; k++) {
    const struct nps_wall_segment *s = &c->a->segs[w->first_segment + k];
    if ((k >= rest_k0 && k <= rest_k1) ||
        (s->angle_rad > 0. && deflected_plate_in_reach(w, &tr, t0, t1, k, s->angle_rad))) {
      test_segment(c, w, s);
    }
  }
}

/** Wall w against the ray: the quick rejection of never_in_band here (inlined in the loops, on the inward part
 * of the track only: n_o and dn), the rest in test_wall_plates. */
static inline void test_wall(struct cast *c, const struct nps_wall *w)
{
  const double x = c->o[0] - w->a[0], y = c->o[1] - w->a[1];
  const double n_o = x * w->n[0] + y * w->n[1], dn = c->d[0] * w->n[0] + c->d[1] * w->n[1];
  if (!never_in_band(n_o, dn, -WALL_FILTER_TOL_M, w->p.hinge_height_m + WALL_FILTER_TOL_M, c->hit->range_m)) {
    test_wall_plates(c, w, n_o, dn);
  }
}

/** Obstacle i against the ray, unless the ray's box misses the obstacle's (few obstacles: each is tested). */
static void test_obstacle(struct cast *c, int i)
{
  const struct nps_obstacle *o = &c->a->obstacles[i];
  const double t_max = c->hit->range_m;
  for (int k = 0; k < 2; k++) {
    const double end = c->o[k] + t_max * c->d[k];
    if (fmax(c->o[k], end) < o->lo_m[k] || fmin(c->o[k], end) > o->hi_m[k]) {
      return;
    }
  }
  double normal[3];
  const double t = nps_obstacle_ray(o, c->o, c->d, normal);
  if (closer(c, t)) {
    set_point_normal(c, t, normal);
    c->hit->kind = NPS_HIT_OBSTACLE;
    c->hit->obstacle = i;
    c->hit->wall = c->hit->segment = c->hit->copter_id = -1;
    c->hit->plate = 0;
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

/** Whether the search is over: in `any` mode at the first hit. */
static int done(const struct cast *c)
{
  return c->any && c->hit->kind != NPS_HIT_NOTHING;
}

/**
 * Walk the grid cells the ray crosses, testing, with walls = 1, the walls listed there and, with copters = 1, the
 * copter bodies, up to the nearest hit so far. A wall's cells form a box, which a straight walk crosses in one
 * run: a wall listed in the previous cell was tested there, over the whole ray.
 */
static void walk_cells(struct cast *c, int walls, int copters)
{
  const struct nps_arena_grid *g = c->a->grid;
  struct nps_arena_grid_walk w;
  int prev = -1;
  for (int more = nps_arena_grid_walk_start(g, c->o, c->d, c->hit->range_m, &w); more;
       more = nps_arena_grid_walk_next(&w)) {
    for (int k = g->reach_start[w.cell]; walls && k < g->reach_start[w.cell + 1]; k++) {
      if (prev < 0 || !cell_lists_wall(g, prev, g->reach_items[k])) {
        test_wall(c, &c->a->walls[g->reach_items[k]]);
      }
    }
    for (int e = copters ? g->body_head[w.cell] : -1; e >= 0; e = g->body_next[e]) {
      test_copter(c, &c->a->copters[e >> g->body_shift]);
    }
    prev = w.cell;
    /* everything listed in later cells is hit beyond t_exit */
    if (done(c) || (c->hit->kind != NPS_HIT_NOTHING && c->hit->range_m <= w.t_exit_m)) {
      return;
    }
  }
}

/**
 * Every surface against the ray, nearest hit in c->hit: the floor and the obstacles, then the copters and the walls,
 * each either
 * one by one (a few copters; with them the walls of a simple polygon, whose plates test_wall picks from the ray's
 * track alone, after the copters) or from the grid cells the ray crosses. A nearest hit found early shortens the rest
 * of the search. Both
 * ways give the same nearest hit (tests compare them); of two surfaces hit at exactly the same range the first
 * one tested is kept, so such a tie between two walls may name either wall.
 */
static inline __attribute__((always_inline)) void cast_ray(struct cast *c)
{
  const struct nps_arena *a = c->a;
  const struct nps_arena_grid *g = a->grid;
  if (c->d[2] < 0. && c->o[2] >= 0.) {
    double t = -c->o[2] / c->d[2];
    if (closer(c, t)) {
      const double up[3] = { 0., 0., 1. };
      set_point_normal(c, t, up);
      c->hit->kind = NPS_HIT_FLOOR;
    }
  }
  for (int i = 0; i < a->num_obstacles && !done(c); i++) {
    test_obstacle(c, i);
  }
  /* the counts and arrays in locals: a hit written through c->hit could alias them as far as the compiler knows */
  const int num_copters = a->num_copters, num_walls = a->num_walls;
  const struct nps_arena_copter *const copters = a->copters;
  const struct nps_wall *const walls = a->walls;
  const int copters_direct = nps_arena_grid_few_copters(g);
  for (int i = 0; copters_direct && i < num_copters && !done(c); i++) {
    test_copter(c, &copters[i]);
  }
  /* with the copters in the grid (a large swarm) the walk stops at the first body: the walls come from it too */
  const int walls_direct = copters_direct && num_walls <= g->direct_max_walls;
  if ((!walls_direct || !copters_direct) && !done(c)) {
    walk_cells(c, !walls_direct, !copters_direct);
  }
  for (int k = 0; !copters_direct && k < g->num_overflow && !done(c); k++) {
    test_copter(c, &copters[g->overflow[k]]);
  }
  /* the walls last: a copter hit before them rejects the far walls from their track alone */
  for (int i = 0; walls_direct && i < num_walls && !done(c); i++) {
    test_wall(c, &walls[i]);
  }
}

/**
 * nps_raycast, or with any = 1 whether anything is hit at all (hit then holds some hit, not the nearest), with
 * geometry = 0 without the hit's point and normal. Always inlined: each caller gets its own copy with `any` and
 * `geometry` constants, the ground-truth ray without the checks for them.
 */
static inline __attribute__((always_inline)) enum nps_hit_kind raycast(const struct nps_arena *a,
    const double origin_m[3], const double dir[3], double max_range_m, int skip_a, int skip_b, int any, int geometry,
    struct nps_ray_hit *hit)
{
  *hit = (struct nps_ray_hit) {
    .kind = NPS_HIT_NOTHING, .range_m = max_range_m, .wall = -1, .segment = -1, .copter_id = -1, .obstacle = -1
  };
  /* a unit dir (the sonars' boresights: mostly a norm of exactly 1) spares the root and the divisions: x / 1 = x
   * exactly; the branch on the squared norm is settled before a root would be */
  const double norm2 = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
  const int unit = nps_geometry_root_is_one(norm2);
  const double norm = unit ? 1. : sqrt(norm2);
  if (norm > 0. && max_range_m >= 0.) {
    struct cast c = {
      .a = a, .o = { origin_m[0], origin_m[1], origin_m[2] }, .d = { dir[0], dir[1], dir[2] }, .skip_a = skip_a,
      .skip_b = skip_b, .hit = hit, .any = any, .geometry = geometry
    };
    for (int k = 0; !unit && k < 3; k++) {
      c.d[k] = dir[k] / norm;
    }
    c.dh2 = c.d[0] * c.d[0] + c.d[1] * c.d[1];
    cast_ray(&c);
  }
  if (hit->kind == NPS_HIT_NOTHING) {
    hit->range_m = INFINITY;
  }
  return hit->kind;
}

enum nps_hit_kind nps_raycast(const struct nps_arena *a, const double origin_m[3], const double dir[3],
                              double max_range_m, int skip_a, int skip_b, struct nps_ray_hit *hit)
{
  return raycast(a, origin_m, dir, max_range_m, skip_a, skip_b, 0, 1, hit);
}

enum nps_hit_kind nps_raycast_range(const struct nps_arena *a, const double origin_m[3], const double dir[3],
                                    double max_range_m, int skip_a, int skip_b, struct nps_ray_hit *hit)
{
  return raycast(a, origin_m, dir, max_range_m, skip_a, skip_b, 0, 0, hit);
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
  double d[3] = { p_b[0] - p_a[0], p_b[1] - p_a[1], p_b[2] - p_a[2] };
  double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  /* without a hit to report, the first one found settles it (and needs no point or normal) */
  return hit != NULL ? raycast(a, p_a, d, len, id_a, id_b, 0, 1, hit) != NPS_HIT_NOTHING
         : raycast(a, p_a, d, len, id_a, id_b, 1, 0, &local) != NPS_HIT_NOTHING;
}
