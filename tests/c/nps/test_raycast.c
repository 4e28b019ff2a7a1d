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
 * @file test_raycast.c
 * Ray casts against known geometry, exactly: walls at rest and deflected, the fixed curtain above the
 * hinge, the sheet behind a lifted plate, copter cylinders (side, chord, cap), the floor, misses and the
 * range limit; the grid walk against a full scan (copters from the cells or one by one, bit for bit; a
 * blocked line's first hit against its nearest); the context values (target copter, facing sonars,
 * blocked line, wall distance), the facing query against a full scan.
 */
#include "test_helpers.h"
#include "test_arena_fixtures.h"
#include "nps_arena.h"
#include "nps_arena_grid.h"
#include "nps_crosstalk.h"
#include "nps_geometry.h"
#include "nps_raycast.h"
#include "nps_walls.h"

#include <gsl/gsl_rng.h>
#include <stddef.h>
#include <string.h>

#define DEG (M_PI / 180.)
#define EXACT 1e-12

/** 3 m x 4 m, 20 plates per wall: wall 1 (east, x = 3) segment 10 spans y in [2.0, 2.2]. */
static struct nps_arena *rectangle(void)
{
  char err[256] = "";
  struct nps_arena *a = nps_arena_new_rectangle(3., 4., 20, err, sizeof err);
  assert_non_null(a);
  return a;
}

static struct nps_wall_segment *segment(struct nps_arena *a, int wall, int index)
{
  return &a->segs[a->walls[wall].first_segment + index];
}

static struct nps_ray_hit cast(const struct nps_arena *a, double ox, double oy, double oz, double dx, double dy,
                               double dz, double max_m, int skip)
{
  const double o[3] = { ox, oy, oz }, d[3] = { dx, dy, dz };
  struct nps_ray_hit h;
  nps_raycast(a, o, d, max_m, skip, NPS_RAYCAST_NO_ID, &h);
  return h;
}

static void walls_at_rest_floor_and_misses(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  /* east: from (1, 2.1, 0.6) along +x the plate at x = 3: 2 m, wall 1 segment 10, normal -x */
  struct nps_ray_hit h = cast(a, 1., 2.1, 0.6, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_close(h.range_m, 2., EXACT);
  assert_int_equal(h.wall, 1);
  assert_int_equal(h.segment, 10);
  assert_int_equal(h.plate, 1);
  assert_close(h.normal[0], -1., EXACT);
  assert_close(h.point_m[0], 3., EXACT);
  /* above the hinge (1 m) the fixed curtain: same distance, plate = 0 */
  h = cast(a, 1., 2.1, 1.5, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_close(h.range_m, 2., EXACT);
  assert_int_equal(h.plate, 0);
  /* over the wall top (2 m): nothing */
  h = cast(a, 1., 2.1, 2.5, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  assert_true(isinf(h.range_m));
  /* within range only: 1.5 m is not enough */
  h = cast(a, 1., 2.1, 0.6, 1., 0., 0., 1.5, NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  /* south-west diagonal at 0.6 m from (1, 1): 1 m south, 1 m west: the corner; 3-4-5 toward north-east */
  h = cast(a, 1., 1., 0.6, 3., 4., 0., 10., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.wall, 1); /* x = 3 reached at t = 2 / 0.6 = 3.333 m, y = 3.667 < 4 */
  assert_close(h.range_m, 2. / 0.6, EXACT);
  /* straight down: the floor at 0.6 m, normal up */
  h = cast(a, 1., 2., 0.6, 0., 0., -1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_FLOOR);
  assert_close(h.range_m, 0.6, EXACT);
  assert_close(h.normal[2], 1., EXACT);
  /* 45 deg down toward the east wall: the floor first, at 0.6 sqrt(2) */
  h = cast(a, 1., 2., 0.6, 1., 0., -1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_FLOOR);
  assert_close(h.range_m, 0.6 * M_SQRT2, EXACT);
  assert_close(h.point_m[0], 1.6, EXACT);
  /* straight up: nothing (no ceiling); zero direction: nothing */
  h = cast(a, 1., 2., 0.6, 0., 0., 1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  h = cast(a, 1., 2., 0.6, 0., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  /* from outside the arena, toward it: the west wall's outer face at x = 0 */
  h = cast(a, -1., 2.1, 0.6, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.wall, 3);
  assert_close(h.range_m, 1., EXACT);
  assert_close(h.normal[0], -1., EXACT);
  nps_arena_free(a);
}

static void deflected_plates_exactly(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  double th = 20. * DEG;
  segment(a, 1, 10)->angle_rad = th;
  /* hinged at 1 m: at height z the plate is (1 - z) tan(th) inside x = 3 */
  struct nps_ray_hit h = cast(a, 1., 2.1, 0.6, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.plate, 1);
  assert_close(h.range_m, 2. - 0.4 * tan(th), EXACT);
  /* plate normal (cos th n, sin th) = (-cos th, 0, sin th), facing the ray */
  assert_close(h.normal[0], -cos(th), EXACT);
  assert_close(h.normal[2], sin(th), EXACT);
  h = cast(a, 1., 2.1, 0.2, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_close(h.range_m, 2. - 0.8 * tan(th), EXACT);
  /* the neighbour (segment 11, y in [2.2, 2.4]) is at rest */
  h = cast(a, 1., 2.3, 0.6, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.segment, 11);
  assert_close(h.range_m, 2., EXACT);
  /* at 70 deg the bottom edge is lifted to 1 - cos 70 = 0.658 m: a ray at 0.3 m passes under it to the
   * sheet at rest behind (plate = 0); at 0.8 m it meets the plate 0.2 tan 70 inside */
  segment(a, 1, 10)->angle_rad = 70. * DEG;
  h = cast(a, 1., 2.1, 0.3, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.plate, 0);
  assert_close(h.range_m, 2., EXACT);
  h = cast(a, 1., 2.1, 0.8, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.plate, 1);
  assert_close(h.range_m, 2. - 0.2 * tan(70. * DEG), EXACT);
  /* looking down onto the lifted plate from above: from (2.9, 2.1, 1.5) straight down the plate is at
   * the height z where (1 - z) tan 70 = 0.1 */
  h = cast(a, 2.9, 2.1, 1.5, 0., 0., -1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.plate, 1);
  assert_close(h.range_m, 1.5 - (1. - 0.1 / tan(70. * DEG)), EXACT);
  nps_arena_free(a);
}

/**
 * Horizontal rays at the edges of the fixed curtain (1 to 2 m) and of the sheet behind a lifted plate (0 to 1 m):
 * a sheet counts within NPS_GEOMETRY_EDGE_TOL_M (1e-9 m) of its edges, not beyond (test_segment's height filter
 * must keep exactly the hits of nps_geometry_ray_rect).
 */
static void sheet_edges_within_the_tolerance(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  struct nps_ray_hit h = cast(a, 1., 2.1, 2. + 0.5e-9, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.plate, 0);
  assert_close(h.range_m, 2., EXACT);
  h = cast(a, 1., 2.1, 2. + 2e-9, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  /* lifted 70 deg: the bottom edge at 0.658 m; under it the sheet from the floor up, to 1e-9 below the floor */
  segment(a, 1, 10)->angle_rad = 70. * DEG;
  h = cast(a, 1., 2.1, -0.5e-9, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.plate, 0);
  assert_close(h.range_m, 2., EXACT);
  h = cast(a, 1., 2.1, -2e-9, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.kind, NPS_HIT_NOTHING);
  nps_arena_free(a);
}

static void copter_bodies_exactly(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  /* copter 7 at (2, 2.1, 0.6): cylinder radius 0.2 m, z in [0.525, 0.675] */
  struct nps_arena_copter c[2] = {
    nps_arena_copter_make(a, 3, 1., 2.1, 0.6, 0.), nps_arena_copter_make(a, 7, 2., 2.1, 0.6, 0.)
  };
  assert_int_equal(nps_arena_set_copters(a, c, 2), 0);
  /* from copter 3's centre along +x (skipping itself): copter 7's side at x = 1.8 */
  struct nps_ray_hit h = cast(a, 1., 2.1, 0.6, 1., 0., 0., 5., 3);
  assert_int_equal(h.kind, NPS_HIT_COPTER);
  assert_int_equal(h.copter_id, 7);
  assert_close(h.range_m, 0.8, EXACT);
  assert_close(h.normal[0], -1., EXACT);
  /* not skipping itself: the ray starts inside copter 3, range 0 */
  h = cast(a, 1., 2.1, 0.6, 1., 0., 0., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.copter_id, 3);
  assert_close(h.range_m, 0., 0.);
  /* skipping both: the wall */
  const double o[3] = { 1., 2.1, 0.6 }, d[3] = { 1., 0., 0. };
  assert_int_equal(nps_raycast(a, o, d, 5., 3, 7, &h), NPS_HIT_WALL);
  assert_close(h.range_m, 2., EXACT);
  /* a chord 0.1 m off the axis: enters at x = 2 - sqrt(0.2^2 - 0.1^2) */
  h = cast(a, 1., 2.2, 0.6, 1., 0., 0., 5., 3);
  assert_int_equal(h.copter_id, 7);
  assert_close(h.range_m, 1. - sqrt(0.03), EXACT);
  /* passing 0.21 m off the axis misses it */
  h = cast(a, 1., 2.31, 0.6, 1., 0., 0., 5., 3);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  /* from above: the top cap at 0.675 m */
  h = cast(a, 2.05, 2.1, 1.5, 0., 0., -1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.copter_id, 7);
  assert_close(h.range_m, 1.5 - 0.675, EXACT);
  assert_close(h.normal[2], 1., EXACT);
  /* straight down beside the axis (a vertical ray never nears it): a millionth inside the rim the cap; outside the
   * rim the floor, whether within the quick rejection's margin (a millionth of the radius: 1e-8 out, left to the
   * exact test) or beyond it (3e-6 out, rejected quickly) */
  const double rim_m = 0.2, in_m = rim_m * (1. - 1e-6), out_m[2] = { rim_m * (1. + 1e-8), rim_m * (1. + 3e-6) };
  h = cast(a, 2. + in_m, 2.1, 1.5, 0., 0., -1., 5., NPS_RAYCAST_NO_ID);
  assert_int_equal(h.copter_id, 7);
  assert_close(h.range_m, 1.5 - 0.675, EXACT);
  for (int k = 0; k < 2; k++) {
    h = cast(a, 2., 2.1 - out_m[k], 1.5, 0., 0., -1., 5., NPS_RAYCAST_NO_ID);
    assert_int_equal(h.kind, NPS_HIT_FLOOR);
  }
  /* a ray at 0.7 m passes over the body (top 0.675 m) */
  h = cast(a, 1., 2.1, 0.7, 1., 0., 0., 5., 3);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  nps_arena_free(a);
}

/**
 * The truth ray's shortcuts, exactly: a squared norm whose root is exactly 1 (checked against sqrt for 2^17 doubles
 * around 1; sqrt is monotonic, so none farther off has a root of 1), and the range-only cylinder test against the
 * general one, bit for bit, over random rays (sides, caps, chords, misses, origins inside, vertical rays).
 */
static void unit_norms_and_range_only_cylinders_exactly(void **state)
{
  (void)state;
  double below = 1., above = 1.;
  for (int k = 0; k < 65536; k++) {
    assert_int_equal(nps_geometry_root_is_one(below), sqrt(below) == 1.);
    assert_int_equal(nps_geometry_root_is_one(above), sqrt(above) == 1.);
    below = nextafter(below, 0.);
    above = nextafter(above, 2.);
  }
  assert_true(nps_geometry_root_is_one(1. + 0x1p-52) && !nps_geometry_root_is_one(1. - 0x1p-53));
  gsl_rng *r = gsl_rng_alloc(gsl_rng_taus2);
  gsl_rng_set(r, 11);
  const double centre[3] = { 0.3, -0.2, 0.6 };
  for (int i = 0; i < 100000; i++) {
    const double o[3] = { 2. * gsl_rng_uniform(r) - 0.7, 2. * gsl_rng_uniform(r) - 1.2, 1.2 * gsl_rng_uniform(r) };
    const double az = 2. * M_PI * gsl_rng_uniform(r), el = i % 4 == 0 ? 0. : i % 4 == 1 ? -M_PI / 2. :
                      M_PI * (gsl_rng_uniform(r) - 0.5);
    const double d[3] = { cos(el) * cos(az), cos(el) * sin(az), sin(el) };
    double normal[3];
    const double t = nps_geometry_ray_cylinder(o, d, centre, 0.2, 0.075, normal);
    const double t_range = nps_geometry_ray_cylinder_range(o, d, centre, 0.2, 0.075);
    if (memcmp(&t, &t_range, sizeof t) != 0) {
      fail_msg("ray %d: %.17g, range-only %.17g", i, t, t_range);
    }
  }
  gsl_rng_free(r);
}

/** Full-scan oracle: every plate (and the curtain above it, and the sheet behind it), copter and the floor. */
static double oracle(const struct nps_arena *a, const double o[3], const double d[3], double max_m, int skip)
{
  double best = max_m;
  for (int i = 0; i < a->num_segments; i++) {
    const struct nps_wall_segment *s = &a->segs[i];
    const struct nps_wall *w = &a->walls[s->wall];
    double sn = sin(s->angle_rad), cs = cos(s->angle_rad);
    double len = hypot(s->b[0] - s->a[0], s->b[1] - s->a[1]);
    struct nps_geometry_rect plate = {
      { s->a[0], s->a[1], 1. }, { w->t[0], w->t[1], 0. }, len, { sn * w->n[0], sn * w->n[1], -cs }, 1.,
      { cs * w->n[0], cs * w->n[1], sn }
    };
    struct nps_geometry_rect sheet = {
      { s->a[0], s->a[1], 0. }, { w->t[0], w->t[1], 0. }, len, { 0., 0., 1. }, 2., { w->n[0], w->n[1], 0. }
    };
    best = fmin(best, fmin(nps_geometry_ray_rect(o, d, &plate), nps_geometry_ray_rect(o, d, &sheet)));
  }
  for (int i = 0; i < a->num_copters; i++) {
    const struct nps_arena_copter *c = &a->copters[i];
    if (c->id != skip) {
      best = fmin(best, nps_geometry_ray_cylinder(o, d, c->pos_m, c->radius_m, 0.5 * c->height_m, NULL));
    }
  }
  if (d[2] < 0.) {
    best = fmin(best, -o[2] / d[2]);
  }
  return best;
}

static void grid_walk_equals_a_full_scan(void **state)
{
  (void)state;
  /* 1000 plates deflected at random, 100 copters, 2000 random rays (fixed seed), some from outside */
  struct nps_arena *a = scaled_swarmlab_arena(250);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 9);
  for (int i = 0; i < a->num_segments; i++) {
    a->segs[i].angle_rad = gsl_rng_uniform(rng) < 0.5 ? 0. : 40. * DEG * gsl_rng_uniform(rng);
  }
  struct nps_arena_copter c[100];
  for (int i = 0; i < 100; i++) {
    c[i] = nps_arena_copter_make(a, i, 0.3 + 14.4 * gsl_rng_uniform(rng), 0.3 + 19.4 * gsl_rng_uniform(rng),
                                 0.3 + 0.6 * gsl_rng_uniform(rng), 0.);
  }
  c[99].pos_m[0] = -8.; /* one far outside the grid */
  assert_int_equal(nps_arena_set_copters(a, c, 100), 0);
  int kinds[4] = { 0, 0, 0, 0 };
  for (int r = 0; r < 2000; r++) {
    double o[3] = { -2. + 19. * gsl_rng_uniform(rng), -2. + 24. * gsl_rng_uniform(rng), 1.2 * gsl_rng_uniform(rng) };
    double az = 2. * M_PI * gsl_rng_uniform(rng), el = r % 3 == 0 ? 0. : -0.3 + 0.4 * gsl_rng_uniform(rng);  /* sonars: el 0 */
    double d[3] = { cos(el) * cos(az), cos(el) * sin(az), sin(el) };
    if (r % 5 == 1) {   /* the down sonar's ray: straight down, next to a copter's rim (within 1e-5 of its radius) */
      const struct nps_arena_copter *q = &a->copters[(int)(100. * gsl_rng_uniform(rng))];
      const double off_m = q->radius_m * (1. + 2e-5 * (gsl_rng_uniform(rng) - 0.5));
      o[0] = q->pos_m[0] + off_m * cos(az);
      o[1] = q->pos_m[1] + off_m * sin(az);
      o[2] = q->pos_m[2] + 0.5;
      d[0] = d[1] = 0.;
      d[2] = -1.;
    }
    double max_m = 0.5 + 8. * gsl_rng_uniform(rng);
    int skip = (int)(100. * gsl_rng_uniform(rng));
    struct nps_ray_hit h, h_direct;
    a->grid->direct_max_copters = 0;        /* copters and walls found through the cells */
    a->grid->direct_max_walls = 0;
    nps_raycast(a, o, d, max_m, skip, NPS_RAYCAST_NO_ID, &h);
    /* every copter (and then every wall) tested one by one: the same hit, bit for bit (no exact ties here) */
    for (int way = 1; way < 4; way++) {
      a->grid->direct_max_copters = way & 1 ? 1000 : 0;
      a->grid->direct_max_walls = way & 2 ? 1000 : 0;
      nps_raycast(a, o, d, max_m, skip, NPS_RAYCAST_NO_ID, &h_direct);
      assert_memory_equal(&h, &h_direct, sizeof h);
    }
    /* without the point and normal: the same surface at the same range */
    struct nps_ray_hit h_range;
    assert_int_equal(nps_raycast_range(a, o, d, max_m, skip, NPS_RAYCAST_NO_ID, &h_range), h.kind);
    assert_true(h_range.range_m == h.range_m && h_range.wall == h.wall && h_range.segment == h.segment &&
                h_range.plate == h.plate && h_range.copter_id == h.copter_id);
    /* a blocked line without a hit to report stops at the first hit found: the same answer */
    const double end[3] = { o[0] + max_m * d[0], o[1] + max_m * d[1], o[2] + max_m * d[2] };
    struct nps_ray_hit line_hit;
    assert_int_equal(nps_raycast_line_blocked(a, o, end, skip, NPS_RAYCAST_NO_ID, NULL),
                     nps_raycast_line_blocked(a, o, end, skip, NPS_RAYCAST_NO_ID, &line_hit));
    double expected = oracle(a, o, d, max_m, skip);
    double got = h.kind == NPS_HIT_NOTHING ? max_m : h.range_m;
    kinds[h.kind]++;
    if (!(fabs(got - expected) <= 1e-12)) {
      print_error("ray %d: grid %.12g (kind %d), full scan %.12g\n", r, got, h.kind, expected);
      fail();
    }
  }
  print_message("# nothing %d, wall %d, copter %d, floor %d\n", kinds[0], kinds[1], kinds[2], kinds[3]);
  assert_true(kinds[0] > 100 && kinds[1] > 100 && kinds[2] > 20 && kinds[3] > 100);
  gsl_rng_free(rng);
  nps_arena_free(a);
}

static void plates_per_metre_is_the_quotient_it_replaced(void **state)
{
  (void)state;
  /* the plate lookup's cached plates per metre is num_segments / length_m bit for bit, in arenas whose quotients
   * are not round numbers (3 m with 20 plates, oblique walls of lengths near 6 m and 5 m: num_segments times a
   * cached 1 / length_m differs there) */
  struct nps_arena *arenas[3] = { rectangle(), turned_rectangle(20), scaled_swarmlab_arena(250) };
  for (int k = 0; k < 3; k++) {
    for (int i = 0; i < arenas[k]->num_walls; i++) {
      const struct nps_wall *w = &arenas[k]->walls[i];
      assert_true(w->plates_per_m == w->p.num_segments / w->length_m);
    }
    nps_arena_free(arenas[k]);
  }
}

/**
 * Range of the ray against every plate and the sheet above it by the general rectangle test, as test_segment built
 * them, in the order it tests them (a plate wins a tie with its sheet); *plate: whether a plate is the nearest,
 * *seg: the index in a->segs of the nearest (-1 if none within max_m).
 */
static double rect_scan(const struct nps_arena *a, const double o[3], const double d[3], double max_m, int *plate_hit,
                        int *seg)
{
  double best = max_m;
  *plate_hit = 0;
  *seg = -1;
  for (int i = 0; i < a->num_segments; i++) {
    const struct nps_wall_segment *s = &a->segs[i];
    const struct nps_wall *w = &a->walls[s->wall];
    const double L = w->p.hinge_height_m, H = a->wall_height_m, sn = sin(s->angle_rad), cs = cos(s->angle_rad);
    const struct nps_geometry_rect plate = {
      { s->a[0], s->a[1], L }, { w->t[0], w->t[1], 0. }, s->length_m, { sn * w->n[0], sn * w->n[1], -cs }, L,
      { cs * w->n[0], cs * w->n[1], sn }
    };
    const struct nps_geometry_rect above = {
      { s->a[0], s->a[1], L }, { w->t[0], w->t[1], 0. }, s->length_m, { 0., 0., 1. }, H - L, { w->n[0], w->n[1], 0. }
    };
    const double t_plate = nps_geometry_ray_rect(o, d, &plate), t_above = nps_geometry_ray_rect(o, d, &above);
    if (t_plate < best) {
      best = t_plate;
      *plate_hit = 1;
      *seg = i;
    }
    if (t_above < best) {
      best = t_above;
      *plate_hit = 0;
      *seg = i;
    }
  }
  return best;
}

/**
 * Every plate of a at rest, no copters: 3000 rays (seed 21) from inside the w_m x h_m rectangle [0.5, w_m - 0.5] x
 * [0.5, h_m - 0.5] turned by turn_rad about the origin, a third of them (drawn) aimed at a plate's corner (the seam)
 * and a third at a point just beyond the seam's edge tolerance on either side (where the rounding of the along-wall
 * coordinate decides), at heights around the hinge (the plate's top edge: within, at and just beyond its tolerance;
 * the curtain above): the range, plate and segment of test_segment's shortcut for a horizontal ray and a plate at
 * rest are the general rectangle test's, bit for bit. One ray in five is tilted by 1e-3 rad (it must not take the
 * shortcut: a tilted ray's height at the plate is not its origin's).
 */
static void rest_plates_as_the_rectangle_test(struct nps_arena *a, double turn_rad, double w_m, double h_m)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 21);
  const double L = a->walls[0].p.hinge_height_m;
  const double tol = NPS_GEOMETRY_EDGE_TOL_M;   /* within, at and just beyond the top edge's tolerance */
  const double heights_m[] = { 0.5 * L, L, L + 0.5 * tol, L - 0.5 * tol, L + tol, L + 1.000001 * tol, L + 2. * tol,
                               0.5 * (L + a->wall_height_m) };
  const int n_heights = (int)(sizeof heights_m / sizeof heights_m[0]);
  int hits = 0, plates = 0;
  for (int r = 0; r < 3000; r++) {
    const double x = 0.5 + (w_m - 1.) * gsl_rng_uniform(rng), y = 0.5 + (h_m - 1.) * gsl_rng_uniform(rng);
    const double o[3] = { cos(turn_rad) * x - sin(turn_rad) * y, sin(turn_rad) * x + cos(turn_rad) * y,
                          heights_m[r % n_heights] };
    double az = 2. * M_PI * gsl_rng_uniform(rng);
    double d[3] = { cos(az), sin(az), r % 5 == 4 ? (r % 2 ? 1e-3 : -1e-3) : 0. };
    const int aim = (int)(3. * gsl_rng_uniform(rng));   /* drawn: independent of the height and the tilt */
    if (aim > 0) {
      const struct nps_wall_segment *s = &a->segs[(int)(a->num_segments * gsl_rng_uniform(rng))];
      const struct nps_wall *w = &a->walls[s->wall];
      /* the seam, or 1.000001 edge tolerances before or after it along the wall */
      const double along_m = aim == 1 ? 0. : (gsl_rng_uniform(rng) < 0.5 ? 1. : -1.) * 1.000001 * tol;
      const double to[2] = { s->a[0] + along_m * w->t[0] - o[0], s->a[1] + along_m * w->t[1] - o[1] };
      const double len = sqrt(to[0] * to[0] + to[1] * to[1]);
      d[0] = to[0] / len;
      d[1] = to[1] / len;
    }
    /* the direction nps_raycast works with: d divided by its norm unless that is exactly 1 */
    const double norm = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double unit[3] = { d[0], d[1], d[2] };
    for (int k = 0; norm != 1. && k < 3; k++) {
      unit[k] = d[k] / norm;
    }
    struct nps_ray_hit h;
    nps_raycast(a, o, d, 100., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &h);
    int plate_hit, seg;
    const double expected = rect_scan(a, o, unit, 100., &plate_hit, &seg);
    const double got = h.kind == NPS_HIT_NOTHING ? 100. : h.range_m;
    const int got_seg = h.kind == NPS_HIT_WALL ? a->walls[h.wall].first_segment + h.segment : -1;
    if (memcmp(&got, &expected, sizeof got) != 0 || h.plate != plate_hit || got_seg != seg) {
      print_error("ray %d: %.17g (kind %d, plate %d, segment %d), rectangle test %.17g (plate %d, segment %d)\n", r,
                  got, h.kind, h.plate, got_seg, expected, plate_hit, seg);
      fail();
    }
    hits += h.kind == NPS_HIT_WALL;
    plates += h.kind == NPS_HIT_WALL && h.plate;
  }
  print_message("# %d wall hits, %d on plates\n", hits, plates);
  assert_true(hits > 2500 && plates > 1000 && plates < hits);
  gsl_rng_free(rng);
  nps_arena_free(a);
}

static void horizontal_rays_meet_plates_at_rest_as_the_rectangle_test(void **state)
{
  (void)state;
  /* walls along the axes: the plates of a wall share the distance across it, so a seam's two plates tie */
  rest_plates_as_the_rectangle_test(scaled_swarmlab_arena(20), 0., 15., 20.);
  /* oblique walls: each plate's range has its own rounding, so the nearest of a seam's two decides (the lower edge
   * tolerance too) */
  rest_plates_as_the_rectangle_test(turned_rectangle(20), TURNED_RECTANGLE_RAD, 6., 5.);
}

static void sonar_poses_and_target_copter(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  /* copter 0 at (1.5, 2) yaw 90 deg (front = north): front sonar 2 m to wall 2, right 1.5 m to wall 1,
   * back 2 m to wall 0, left 1.5 m to wall 3, down 0.6 m to the floor */
  struct nps_arena_copter c[2] = {
    nps_arena_copter_make(a, 0, 1.5, 2., 0.6, M_PI / 2.), nps_arena_copter_make(a, 1, 1.5, 3., 0.6, 0.)
  };
  assert_int_equal(nps_arena_set_copters(a, c, 1), 0);
  const double expect[NPS_SONAR_COUNT] = { 2., 1.5, 2., 1.5, 0.6 };
  const int wall[NPS_SONAR_COUNT] = { 2, 1, 0, 3, -1 };
  for (int s = 0; s < NPS_SONAR_COUNT; s++) {
    struct nps_ray_hit h;
    nps_raycast_sonar(a, &c[0], (enum nps_sonar)s, 3., &h);
    assert_close(h.range_m, expect[s], EXACT);
    assert_int_equal(h.wall, wall[s]);
  }
  assert_string_equal(nps_sonar_name(NPS_SONAR_LEFT), "sonar_left");
  /* ctx_target_copter: copter 1 ahead at 1 m: the front sonar's first hit is its body at 0.8 m */
  assert_int_equal(nps_arena_set_copters(a, c, 2), 0);
  struct nps_ray_hit h;
  assert_int_equal(nps_raycast_sonar(a, &c[0], NPS_SONAR_FRONT, 3., &h), NPS_HIT_COPTER);
  assert_int_equal(h.copter_id, 1);
  assert_close(h.range_m, 0.8, EXACT);
  nps_arena_free(a);
}

/** The boresight of each sonar for a copter of heading yaw: (cos, sin)(yaw + heading) or straight down. */
static void boresight_by_sum(double yaw_rad, int s, double b[3])
{
  const double heading_rad[4] = { 0., -M_PI / 2., M_PI, M_PI / 2. };
  b[0] = s == NPS_SONAR_DOWN ? 0. : cos(yaw_rad + heading_rad[s]);
  b[1] = s == NPS_SONAR_DOWN ? 0. : sin(yaw_rad + heading_rad[s]);
  b[2] = s == NPS_SONAR_DOWN ? -1. : 0.;
}

static void sonar_boresights_from_the_yaw_memo(void **state)
{
  (void)state;
  /* 1000 headings over +-10 turns: the quarter-turned (cos yaw, sin yaw) is (cos, sin)(yaw + heading) but for the
   * rounding of the sum, within 1.2e-16 (|yaw| + 4) + 2 ulp per component; the memo (nps_arena_copter_make, set_copters)
   * gives the same bits as a copter built by hand (no memo) or one whose yaw changed after its memo (stale) */
  struct nps_arena *a = rectangle();
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  for (int i = 0; i < 1000; i++) {
    const double yaw = 2. * M_PI * (20. * gsl_rng_uniform(rng) - 10.);
    struct nps_arena_copter made = nps_arena_copter_make(a, 0, 1.5, 2., 0.6, yaw);
    struct nps_arena_copter by_hand = { .id = 0, .pos_m = { 1.5, 2., 0.6 }, .yaw_rad = yaw, .radius_m = 0.1,
                                        .height_m = 0.1 };
    struct nps_arena_copter stale = nps_arena_copter_make(a, 0, 1.5, 2., 0.6, yaw + 1.);
    stale.yaw_rad = yaw;
    assert_true(made.yaw_trig_valid && made.cos_yaw == cos(yaw) && made.sin_yaw == sin(yaw));
    assert_int_equal(nps_arena_set_copters(a, &by_hand, 1), 0);
    assert_true(a->copters[0].yaw_trig_valid && a->copters[0].sin_yaw == sin(yaw));
    for (int s = 0; s < NPS_SONAR_COUNT; s++) {
      double o_made[3], b_made[3], o_hand[3], b_hand[3], o_stale[3], b_stale[3], b_sum[3];
      nps_raycast_sonar_pose(a, &made, (enum nps_sonar)s, o_made, b_made);
      nps_raycast_sonar_pose(a, &by_hand, (enum nps_sonar)s, o_hand, b_hand);
      nps_raycast_sonar_pose(a, &stale, (enum nps_sonar)s, o_stale, b_stale);
      assert_memory_equal(b_made, b_hand, sizeof b_made);
      assert_memory_equal(b_made, b_stale, sizeof b_made);
      assert_memory_equal(o_made, o_stale, sizeof o_made);
      boresight_by_sum(yaw, s, b_sum);
      for (int k = 0; k < 3; k++) {
        assert_close(b_made[k], b_sum[k], 1.2e-16 * (fabs(yaw) + 4.) + 4.5e-16);
      }
    }
  }
  gsl_rng_free(rng);
  nps_arena_free(a);
}

static void facing_sonars_blocked_lines_and_wall_distance(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle();
  double half = 15. * DEG;
  /* 0 at (1.5, 1) looks north, 1 at (1.5, 3) looks south: the front sonars face each other at 2 m */
  struct nps_arena_copter c[3] = {
    nps_arena_copter_make(a, 0, 1.5, 1., 0.6, M_PI / 2.), nps_arena_copter_make(a, 1, 1.5, 3., 0.6, -M_PI / 2.),
    nps_arena_copter_make(a, 2, 0.5, 2., 0.6, 0.)
  };
  assert_int_equal(nps_arena_set_copters(a, c, 3), 0);
  struct nps_facing_sonar f[4];
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 3., f, 4), 1);
  assert_int_equal(f[0].copter_id, 1);
  assert_int_equal(f[0].sonar, NPS_SONAR_FRONT);
  assert_close(f[0].path_m, 2., EXACT);
  assert_close(f[0].off_axis_rad, 0., 1e-7);
  assert_int_equal(f[0].blocked, 0);
  /* 0's back sonar faces nothing; copter 1 turned by 14 deg still faces, by 16 deg not */
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_BACK, half, 3., NULL, 0), 0);
  c[1].yaw_rad = -M_PI / 2. + 14. * DEG;
  assert_int_equal(nps_arena_set_copters(a, c, 3), 0);
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 3., f, 4), 1);
  assert_close(f[0].off_axis_rad, 14. * DEG, 1e-9);
  c[1].yaw_rad = -M_PI / 2. + 16. * DEG;
  assert_int_equal(nps_arena_set_copters(a, c, 3), 0);
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 3., f, 4), 0);
  /* out of range: 2 m apart, range 1.9 m */
  c[1].yaw_rad = -M_PI / 2.;
  assert_int_equal(nps_arena_set_copters(a, c, 3), 0);
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 1.9, NULL, 0), 0);
  /* ctx_blocked: copter 2 moved between them cuts the line; the facing entry says so */
  struct nps_ray_hit h;
  assert_int_equal(nps_raycast_line_blocked(a, c[0].pos_m, c[1].pos_m, 0, 1, &h), 0);
  c[2].pos_m[0] = 1.5;
  assert_int_equal(nps_arena_set_copters(a, c, 3), 0);
  assert_int_equal(nps_raycast_line_blocked(a, c[0].pos_m, c[1].pos_m, 0, 1, &h), 1);
  assert_int_equal(h.kind, NPS_HIT_COPTER);
  assert_int_equal(h.copter_id, 2);
  assert_close(h.range_m, 0.8, EXACT);
  /* copter 2 (yaw 0) now also faces copter 0 with its right sonar, 1 m away, unblocked: nearest first */
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 3., f, 4), 2);
  assert_int_equal(f[0].copter_id, 2);
  assert_int_equal(f[0].sonar, NPS_SONAR_RIGHT);
  assert_close(f[0].path_m, 1., EXACT);
  assert_int_equal(f[0].blocked, 0);
  assert_int_equal(f[1].copter_id, 1);
  assert_int_equal(f[1].blocked, 1);
  /* only the nearest when out has room for one */
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, half, 3., f, 1), 2);
  assert_int_equal(f[0].copter_id, 2);
  /* ctx_wall_dist: horizontal distance to the nearest wall at rest */
  const double p[3] = { 2.9, 1., 0.6 }, q[3] = { 1.5, 2., 0.6 };
  assert_close(nps_raycast_wall_dist(a, p), 0.1, EXACT);
  assert_close(nps_raycast_wall_dist(a, q), 1.5, EXACT);
  nps_arena_free(a);
}

static void line_across_a_notch_is_blocked_by_the_wall(void **state)
{
  (void)state;
  /* an L-shaped arena, corners (0,0) (4,0) (4,2) (2,2) (2,4) (0,4): the notch x > 2, y > 2 is outside */
  char err[256] = "";
  const double xy[7][2] = { { 0, 0 }, { 4, 0 }, { 4, 2 }, { 2, 2 }, { 2, 4 }, { 0, 4 }, { 0, 0 } };
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "L-shape");
  cfg.num_points = 7;
  cfg.points = calloc(7, sizeof * cfg.points);
  cfg.walls = calloc(6, sizeof * cfg.walls);
  assert_non_null(cfg.points);
  assert_non_null(cfg.walls);
  for (int i = 0; i < 7; i++) {
    cfg.points[i].x_m = xy[i][0];
    cfg.points[i].y_m = xy[i][1];
  }
  for (int i = 0; i < 6; i++) {
    nps_wall_params_default(&cfg.walls[i]);
    cfg.walls[i].num_segments = 4;
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  /* from (1, 3.5) to (3.5, 1) the line x + y = 4.5 leaves the arena through wall 3 (x = 2) at y = 2.5 */
  const double p1[3] = { 1., 3.5, 0.6 }, p2[3] = { 3.5, 1., 0.6 }, p3[3] = { 1., 1., 0.6 };
  struct nps_ray_hit h;
  assert_int_equal(nps_raycast_line_blocked(a, p1, p2, 0, 1, &h), 1);
  assert_int_equal(h.kind, NPS_HIT_WALL);
  assert_int_equal(h.wall, 3);
  assert_close(h.range_m, M_SQRT2, EXACT);
  /* along the bottom strip nothing is in the way */
  assert_int_equal(nps_raycast_line_blocked(a, p3, p2, 0, 1, &h), 0);
  nps_arena_free(a);
}

/** Facing sonars of copter i's sonar s by a scan of every pair, nearest first (stable), at most max_out. */
static int facing_by_full_scan(const struct nps_arena *a, const struct nps_arena_copter *c, int n, int i, int s,
                               double half, double range, struct nps_facing_sonar *out, int max_out)
{
  double pr[3], br[3];
  int count = 0;
  nps_raycast_sonar_pose(a, &c[i], (enum nps_sonar)s, pr, br);
  for (int j = 0; j < n; j++) {
    for (int k = 0; j != i && k < NPS_SONAR_COUNT; k++) {
      double pe[3], be[3], path;
      nps_raycast_sonar_pose(a, &c[j], (enum nps_sonar)k, pe, be);
      if (!nps_crosstalk_facing(pr, br, pe, be, half, range, &path)) {
        continue;
      }
      int at = count < max_out ? count : max_out;
      while (at > 0 && out[at - 1].path_m > path) {
        if (at < max_out) {
          out[at] = out[at - 1];
        }
        at--;
      }
      if (at < max_out) {
        out[at] = (struct nps_facing_sonar) { .copter_id = c[j].id, .sonar = (enum nps_sonar)k, .path_m = path };
      }
      count++;
    }
  }
  return count;
}

static void facing_query_equals_a_full_scan(void **state)
{
  (void)state;
  /* beams of 30 deg (no two sonars of a copter can face the same point), 50 deg (two can), 15 deg with the
   * sonars 5 cm off the centre; headings far from 0 (the cheap emitter test's bound grows with |yaw|) */
  const struct { double half_deg, offset_m, yaw_turns; } cases[] = { { 30., 0., 0. }, { 50., 0., 1000. },
    { 15., 0.05, -3. } };
  struct nps_arena *a = scaled_swarmlab_arena(20);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  for (size_t t = 0; t < sizeof cases / sizeof cases[0]; t++) {
    a->sonar_offset_m = cases[t].offset_m;
    struct nps_arena_copter c[100];
    for (int i = 0; i < 100; i++) {
      c[i] = nps_arena_copter_make(a, i, 0.3 + 14.4 * gsl_rng_uniform(rng), 0.3 + 19.4 * gsl_rng_uniform(rng),
                                   0.3 + 0.9 * gsl_rng_uniform(rng),
                                   2. * M_PI * (cases[t].yaw_turns + gsl_rng_uniform(rng)));
    }
    assert_int_equal(nps_arena_set_copters(a, c, 100), 0);
    const double half = cases[t].half_deg * DEG, range = 3.;
    int total = 0;
    /* each receiver twice: candidates from the grid cells of the beam's box, then every copter visited (the loop of a
     * small swarm) */
    for (int pass = 0; pass < 200; pass++) {
      const int i = pass % 100;
      a->grid->direct_max_copters = pass < 100 ? 0 : 1000;
      for (int s = 0; s < NPS_SONAR_COUNT; s++) {
        struct nps_facing_sonar expected[3], got[3], nearest[3];
        const int n = facing_by_full_scan(a, c, 100, i, s, half, range, expected, 3);
        assert_int_equal(nps_raycast_facing_sonars(a, &c[i], (enum nps_sonar)s, half, range, NULL, 0), n);
        assert_int_equal(nps_raycast_facing_sonars(a, &c[i], (enum nps_sonar)s, half, range, got, 3), n);
        double pr[3], br[3];
        nps_raycast_sonar_pose(a, &c[i], (enum nps_sonar)s, pr, br);
        assert_int_equal(nps_raycast_facing_nearest(a, c[i].id, pr, br, cos(half), range, nearest, 3), n);
        for (int k = 0; k < n && k < 3; k++) {
          assert_int_equal(got[k].copter_id, expected[k].copter_id);
          assert_int_equal(got[k].sonar, expected[k].sonar);
          assert_true(got[k].path_m == expected[k].path_m);
          assert_memory_equal(&nearest[k], &got[k], offsetof(struct nps_facing_sonar, emitter_dir));
          assert_true(isnan(nearest[k].emitter_dir[0]) && isnan(nearest[k].off_axis_rad) && nearest[k].blocked == -1);
          assert_int_equal(got[k].blocked, nps_raycast_line_blocked(a, got[k].emitter_pos_m, pr, got[k].copter_id,
                                                                    c[i].id, NULL));
          assert_true(got[k].off_axis_rad <= half + 1e-9 && got[k].rx_off_axis_rad <= half + 1e-9);
        }
        total += n;
      }
    }
    a->grid->direct_max_copters = NPS_ARENA_GRID_DIRECT_MAX;
    print_message("# half-angle %g deg, offset %g m: %d facing pairs among 100 copters (both ways)\n",
                  cases[t].half_deg, cases[t].offset_m, total);
    assert_true(total > 40);
  }
  gsl_rng_free(rng);
  nps_arena_free(a);
}

static void down_sonar_faces_a_receiver_below(void **state)
{
  (void)state;
  /* beams of 50 deg: a copter 0.6 m ahead of and 0.6 m above the receiver (45 deg up) has the receiver's
   * front sonar in its down beam, and is in that sonar's beam (turned 46 deg, its back sonar is 60 deg off); 0.6 m
   * higher still (63 deg) it is out of both */
  struct nps_arena *a = rectangle();
  struct nps_arena_copter c[2] = { nps_arena_copter_make(a, 1, 1.5, 2., 0.5, 0.),
                                   nps_arena_copter_make(a, 2, 2.1, 2., 1.1, 0.8) };
  assert_int_equal(nps_arena_set_copters(a, c, 2), 0);
  struct nps_facing_sonar f[2];
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, 50. * DEG, 3., f, 2), 1);
  assert_int_equal(f[0].copter_id, 2);
  assert_int_equal(f[0].sonar, NPS_SONAR_DOWN);
  assert_close(f[0].path_m, 0.6 * M_SQRT2, EXACT);
  c[1].pos_m[2] = 1.7;
  assert_int_equal(nps_arena_set_copters(a, c, 2), 0);
  assert_int_equal(nps_raycast_facing_sonars(a, &c[0], NPS_SONAR_FRONT, 50. * DEG, 3., f, 2), 0);
  nps_arena_free(a);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(walls_at_rest_floor_and_misses),
    cmocka_unit_test(deflected_plates_exactly),
    cmocka_unit_test(sheet_edges_within_the_tolerance),
    cmocka_unit_test(copter_bodies_exactly),
    cmocka_unit_test(unit_norms_and_range_only_cylinders_exactly),
    cmocka_unit_test(grid_walk_equals_a_full_scan),
    cmocka_unit_test(plates_per_metre_is_the_quotient_it_replaced),
    cmocka_unit_test(horizontal_rays_meet_plates_at_rest_as_the_rectangle_test),
    cmocka_unit_test(sonar_poses_and_target_copter),
    cmocka_unit_test(sonar_boresights_from_the_yaw_memo),
    cmocka_unit_test(facing_sonars_blocked_lines_and_wall_distance),
    cmocka_unit_test(line_across_a_notch_is_blocked_by_the_wall),
    cmocka_unit_test(facing_query_equals_a_full_scan),
    cmocka_unit_test(down_sonar_faces_a_receiver_below),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
