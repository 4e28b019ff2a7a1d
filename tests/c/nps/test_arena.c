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
 * @file test_arena.c
 * Arena loading and construction: the SwarmLab file, every bad-input case with its file:line and reason,
 * arenas built in code (rectangle, scaled, clockwise), copter input checks, the wall snapshot CSV,
 * the NPS-shaped hook, and the copter grid kept up to date copter by copter against a fresh index.
 */
#include "test_helpers.h"
#include "nps_arena.h"
#include "nps_arena_grid.h"
#include "nps_arena_snapshot.h"
#include "nps_walls.h"

#include <gsl/gsl_rng.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SWARMLAB "conf/arena/swarmlab.xml"
#define BAD(name) "tests/data/arena/" name

static void swarmlab_file_is_the_report_arena(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena *a = nps_arena_load(SWARMLAB, err, sizeof err);
  if (!a) {
    print_error("%s\n", err);
  }
  assert_non_null(a);
  assert_int_equal(a->num_walls, 4);
  assert_int_equal(a->num_segments, 80);
  assert_close(a->flight_height_m, 0.6, 0.);
  const double len[4] = { 3., 4., 3., 4. };
  const double normal[4][2] = { { 0., 1. }, { -1., 0. }, { 0., -1. }, { 1., 0. } }; /* into the arena */
  for (int w = 0; w < 4; w++) {
    const struct nps_wall *wall = &a->walls[w];
    assert_close(wall->length_m, len[w], 1e-12);
    assert_close(wall->n[0], normal[w][0], 1e-12);
    assert_close(wall->n[1], normal[w][1], 1e-12);
    /* the report's values, section 2.4.2 */
    assert_int_equal(wall->p.num_segments, 20);
    assert_close(wall->p.segment_mass_kg, 40., 0.);
    assert_close(wall->p.joint_force_nm, 15., 0.);
    assert_close(wall->p.threshold_m, 1., 0.);
    assert_close(wall->p.friction_nm, 3., 0.);
    assert_close(wall->p.max_amplitude_deg, 30., 0.);
    assert_close(wall->p.pid_p, 1., 0.);
    assert_close(wall->p.pid_i, 2., 0.);
    assert_close(wall->p.pid_d, 1., 0.);
    assert_close(wall->p.wall_width_m, len[w], 0.);
    /* J = m L^2 / 3 with L = 1 m */
    assert_close(wall->inertia_kgm2, 40. / 3., 1e-12);
  }
  /* wall 1 (east) segment 3 spans y in [0.6, 0.8] at x = 3 */
  const struct nps_wall_segment *s = &a->segs[a->walls[1].first_segment + 3];
  assert_int_equal(s->wall, 1);
  assert_int_equal(s->index, 3);
  assert_close(s->a[0], 3., 1e-12);
  assert_close(s->a[1], 0.6, 1e-12);
  assert_close(s->b[1], 0.8, 1e-12);
  assert_close(a->copter_radius_m, 0.2, 0.);
  assert_close(a->sonar_range_m, 3.0, 0.);
  nps_arena_free(a);
}

/** A bad file: its error starts with "file:line: " and names the problem. */
struct bad_case {
  const char *file;
  int line;                 /* 0: no line (the file cannot be read) */
  const char *reason;
};

static const struct bad_case bad_cases[] = {
  { BAD("not_closed.xml"), 8, "the polygon is not closed: its last point (0, 4) must repeat its first point (0, 0)" },
  { BAD("self_intersecting.xml"), 7, "the polygon intersects itself: wall 0 (from point 0) and wall 2 (from point 2) meet at (1.5, 2)" },
  { BAD("folds_back.xml"), 6, "the polygon intersects itself: wall 0 (from point 0) and wall 1" },
  { BAD("huge_coordinate.xml"), 6, "<point> x=\"1e100\": expected a number of at most 10000 m in magnitude" },
  { BAD("repeated_point.xml"), 7, "point (3, 0) repeats the previous point: a wall of length 0" },
  { BAD("too_few_points.xml"), 4, "the polygon has 3 point(s): it needs at least 3 corners" },
  { BAD("zero_segments.xml"), 11, "<walls> numSegments=\"0\": expected a whole number >= 1" },
  { BAD("negative_segments.xml"), 11, "<walls> numSegments=\"-5\": expected a whole number >= 1" },
  { BAD("fractional_segments.xml"), 11, "<walls> numSegments=\"2.5\": expected a whole number >= 1" },
  { BAD("negative_mass.xml"), 11, "<walls> segmentMass=\"-40\": expected a mass > 0 kg" },
  { BAD("zero_curtain_mass.xml"), 11, "<walls> curtainMass=\"0\": expected a mass > 0 kg" },
  { BAD("zero_gain.xml"), 11, "<walls> PID_P=\"0\": expected a gain > 0 N m/deg" },
  { BAD("negative_gain.xml"), 11, "<walls> PID_D=\"-1\": expected a gain >= 0 N m s/deg" },
  { BAD("negative_wall_gain.xml"), 12, "<wall> PID_I=\"-2\": expected a gain >= 0 N m/(deg s)" },
  { BAD("not_a_number.xml"), 11, "<walls> jointForce=\"strong\": expected a torque > 0 N m" },
  { BAD("too_small.xml"), 4, "a copter of radius 0.2 m cannot fit in the polygon: its largest inscribed circle has radius 0.15" },
  { BAD("too_low.xml"), 3, "a copter 0.15 m tall at flightHeight 1.98 m does not fit between the floor and the wall top at 2 m" },
  { BAD("unknown_element.xml"), 11, "unknown element <door> in <arena>" },
  { BAD("unknown_attribute.xml"), 11, "unknown attribute 'colour' on <walls>" },
  { BAD("wall_width_mismatch.xml"), 11, "wall 1: wallWidth = 3 m but its polygon edge is 4 m long" },
  { BAD("duplicate_wall.xml"), 12, "<wall> edge=\"1\" is given twice (first at line 11)" },
  { BAD("edge_out_of_range.xml"), 11, "<wall> edge=\"4\": expected a wall index in [0, 3]" },
  { BAD("no_polygon.xml"), 3, "<arena> needs a <polygon>" },
  { BAD("hinge_above_wall.xml"), 11, "wall 0: hingeHeight = 2.5 m is above the wall height 2 m" },
  /* found by tests/fuzz/fuzz_arena_xml.c: the walls took 2e27 sub-steps of a step (an int overflow) */
  { BAD("stiff_walls.xml"), 11, "wall 0: its plates would need integration steps of 4.82e-30 s, shorter than 1e-06 s" },
  { BAD("heavy_curtain.xml"), 11, "wall 0: segmentMass = 40 kg or curtainMass = 1e+308 kg is too heavy to simulate" },
  { BAD("too_many_plates.xml"), 11, "wall 3: numSegments = 30000 makes more than 100000 plates in all" },
  { BAD("wrong_root.xml"), 3, "expected <arena> as the root element, found <airframe>" },
  { BAD("malformed.xml"), 6, "malformed XML: " },
  { BAD("obstacle_outside.xml"), 10, "obstacle 0 lies outside the arena's polygon" },
  { BAD("obstacle_on_wall.xml"), 10, "obstacle 0 overlaps wall 1 (from (3, 0) to (3, 4))" },
  { BAD("obstacle_circle_on_wall.xml"), 10, "obstacle 0 overlaps wall 3" },
  { BAD("obstacle_self_intersecting.xml"), 14, "the polygon intersects itself: edge 0 (from point 0) and edge 2 (from point 2) meet at (1.5, 1.5)" },
  { BAD("obstacles_overlap.xml"), 13, "obstacle 1 overlaps obstacle 0 (line 10)" },
  { BAD("obstacle_no_shape.xml"), 10, "<obstacle> needs a <circle> or a <polygon>" },
  { BAD("obstacle_zero_height.xml"), 10, "obstacle 0: height 0 m: expected a height > 0 m" },
  { BAD("obstacle_not_closed.xml"), 14, "the obstacle's <polygon> needs at least 3 corners and a last point repeating the first" },
  { BAD("does_not_exist.xml"), 0, "cannot read the arena file" },
};

static void each_bad_file_gives_its_error(void **state)
{
  (void)state;
  for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
    const struct bad_case *c = &bad_cases[i];
    char err[512] = "";
    char where[300];
    if (c->line > 0) {
      snprintf(where, sizeof where, "%s:%d: ", c->file, c->line);
    } else {
      snprintf(where, sizeof where, "%s: ", c->file);
    }
    struct nps_arena *a = nps_arena_load(c->file, err, sizeof err);
    if (a || strncmp(err, where, strlen(where)) != 0 || !strstr(err, c->reason)) {
      print_error("%s\n  got:      %s\n  expected: %s%s...\n", c->file, err, where, c->reason);
      nps_arena_free(a);
      fail();
    }
  }
}

/** A copter 0.15 m tall under curtains 2 m high: its centre above 0.075 m and at most 1.925 m (the host's altitude). */
static void a_flight_height_fits_between_floor_and_wall_top(void **state)
{
  (void)state;
  assert_true(nps_arena_height_fits(0.15, 2.0, 0.6));
  assert_true(nps_arena_height_fits(0.15, 2.0, 1.925));
  assert_true(nps_arena_height_fits(0.15, 2.0, nextafter(0.075, 1.0)));
  assert_false(nps_arena_height_fits(0.15, 2.0, 0.075));                  /* the body touches the floor */
  assert_false(nps_arena_height_fits(0.15, 2.0, nextafter(1.925, 2.0)));  /* above the curtains */
  assert_false(nps_arena_height_fits(0.15, 2.0, -1.0));                   /* FINKEN_ALTITUDE=-1: underground */
  assert_false(nps_arena_height_fits(0.15, 2.0, 0.0));
  assert_false(nps_arena_height_fits(0.15, 2.0, NAN));
}

static void rectangle_and_scale_from_code(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "benchmark");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 3., 4., 250, err, sizeof err), 0);
  /* 100 copters at the density of 4 in 3 m x 4 m: 25 times the area, 5 times the sides */
  assert_int_equal(nps_arena_config_scale(&cfg, 5., err, sizeof err), 0);
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  assert_int_equal(a->num_segments, 1000);
  assert_close(a->walls[0].length_m, 15., 1e-12);
  assert_close(a->walls[1].length_m, 20., 1e-12);
  assert_close(a->walls[0].p.threshold_m, 1., 0.); /* scaling keeps the physics */
  nps_arena_free(a);

  nps_arena_config_init(&cfg, "benchmark");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 3., 4., 20, err, sizeof err), 0);
  assert_int_equal(nps_arena_config_scale(&cfg, 0., err, sizeof err), -1);
  assert_string_equal(err, "benchmark: scale factor 0: expected a finite number > 0");
  nps_arena_config_free(&cfg);
}

static void code_errors_name_the_wall(void **state)
{
  (void)state;
  char err[512] = "";
  assert_null(nps_arena_new_rectangle(3., 4., 0, err, sizeof err));
  assert_string_equal(err, "rectangle 3 m x 4 m: wall 0: numSegments = 0: expected a whole number >= 1");
  assert_null(nps_arena_new_rectangle(0.3, 0.3, 4, err, sizeof err));
  assert_non_null(strstr(err, "cannot fit in the polygon"));
}

static void clockwise_polygon_has_inward_normals(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "clockwise");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 3., 4., 5, err, sizeof err), 0);
  /* reverse the corners: (0,0) (0,4) (3,4) (3,0) (0,0) */
  for (int i = 0; i < 2; i++) {
    struct nps_arena_point t = cfg.points[i];
    cfg.points[i] = cfg.points[4 - i];
    cfg.points[4 - i] = t;
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  /* wall 0 runs from (0,0) to (0,4): the west wall, whose inside is +x */
  assert_close(a->walls[0].n[0], 1., 1e-12);
  assert_close(a->walls[0].n[1], 0., 1e-12);
  nps_arena_free(a);
}

static void copters_are_checked(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena *a = nps_arena_new_rectangle(3., 4., 20, err, sizeof err);
  assert_non_null(a);
  struct nps_arena_copter c = nps_arena_copter_make(a, 3, 1., 1., 0.6, 0.);
  assert_close(c.radius_m, 0.2, 0.);
  assert_int_equal(nps_arena_set_copters(a, &c, 1), 0);
  assert_int_equal(nps_arena_copter_index(a, 3), 0);
  assert_int_equal(nps_arena_copter_index(a, 4), -1);
  c.id = -1;
  errno = 0;
  assert_int_equal(nps_arena_set_copters(a, &c, 1), -1);
  assert_int_equal(errno, EINVAL);
  c.id = 1;
  c.pos_m[0] = NAN;
  assert_int_equal(nps_arena_set_copters(a, &c, 1), -1);
  c.pos_m[0] = 1.;
  c.radius_m = 0.;
  assert_int_equal(nps_arena_set_copters(a, &c, 1), -1);
  /* each number of the pose and the size, NaN or infinite in turn, is refused; the copter as it was is fine */
  const struct nps_arena_copter good = nps_arena_copter_make(a, 1, 1., 1., 0.6, 0.);
  const double bad[3] = { NAN, INFINITY, -INFINITY };
  for (int field = 0; field < 6; field++) {
    for (int b = 0; b < 3; b++) {
      c = good;
      double *x[6] = { &c.pos_m[0], &c.pos_m[1], &c.pos_m[2], &c.yaw_rad, &c.radius_m, &c.height_m };
      *x[field] = bad[b];
      assert_int_equal(nps_arena_set_copters(a, &c, 1), -1);
    }
  }
  assert_int_equal(nps_arena_set_copters(a, &good, 1), 0);
  nps_arena_free(a);
}

static void snapshot_csv_has_one_row_per_segment(void **state)
{
  (void)state;
  char err[512] = "";
  char path[] = "/tmp/test_arena_snapshot_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  close(fd);
  struct nps_arena *a = nps_arena_new_rectangle(3., 4., 2, err, sizeof err);
  assert_non_null(a);
  a->segs[1].angle_rad = M_PI / 6.; /* wall 0, segment 1: 30 deg */
  assert_int_equal(nps_arena_snapshot_file(a, path, 0, err, sizeof err), 0);
  assert_int_equal(nps_arena_walls_step(a, 0.5), 0);
  assert_int_equal(nps_arena_snapshot_file(a, path, 1, err, sizeof err), 0);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  char line[512];
  int rows = 0, headers = 0;
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "t,", 2) == 0) {
      assert_string_equal(line,
                          "t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven\n");
      headers++;
    } else {
      rows++;
    }
    if (rows == 2 && headers == 1 && strncmp(line, "0.000000,0,1,", 13) == 0) {
      /* x0 y0 x1 y1 = 1.5 0 3 0, n = (0, 1), 30 deg, 0.4 tan 30 at 0.6 m, sin 30 at the bottom edge */
      double v[11];
      int n = sscanf(line, "%*f,%*d,%*d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                     &v[5], &v[6], &v[7], &v[8], &v[9], &v[10]);
      assert_int_equal(n, 11);
      assert_close(v[0], 1.5, 1e-9);
      assert_close(v[2], 3., 1e-9);
      assert_close(v[5], 1., 1e-9);
      assert_close(v[6], 30., 1e-6);
      assert_close(v[7], 0.4 * tan(M_PI / 6.), 1e-8);
      assert_close(v[8], 0.5, 1e-8);
    }
  }
  fclose(f);
  unlink(path);
  assert_int_equal(headers, 1);
  assert_int_equal(rows, 16);
  nps_arena_free(a);
}

static void hook_loads_steps_and_reports_errors(void **state)
{
  (void)state;
  nps_walls_run_step(0.); /* before init: nothing */
  assert_null(nps_walls_arena());
  assert_int_equal(nps_walls_init(BAD("zero_gain.xml")), -1);
  assert_non_null(strstr(nps_walls_error(), "zero_gain.xml:11: <walls> PID_P=\"0\""));
  assert_null(nps_walls_arena());
  assert_int_equal(nps_walls_init(SWARMLAB), 0);
  struct nps_arena *a = nps_walls_arena();
  assert_non_null(a);
  struct nps_arena_copter c = nps_arena_copter_make(a, 0, 1.5, 0.5, 0.6, 0.);
  assert_int_equal(nps_walls_set_copters(&c, 1), 0);
  for (int k = 0; k <= 512; k++) {
    nps_walls_run_step(k / 512.);
  }
  assert_close(a->time_s, 1., 0.);
  assert_true(a->segs[10].angle_rad > 0.); /* wall 0 under the copter moved */
  nps_walls_run_step(0.5);                  /* backwards: refused, reported */
  assert_non_null(strstr(nps_walls_error(), "before the last step"));
  assert_close(a->time_s, 1., 0.);
  nps_walls_free();
  assert_null(nps_walls_arena());
}

/** Every list of the copter grid of a as text (cells in order, then overflow and by_cell). */
static char *grid_lists(const struct nps_arena *a)
{
  const struct nps_arena_grid *g = a->grid;
  size_t cap = 1 << 16, len = 0;
  char *out = malloc(cap);
  assert_non_null(out);
  for (int cell = 0; cell < g->nx * g->ny; cell++) {
    for (int list = 0; list < 2; list++) {
      int i = list == 0 ? g->body_head[cell] : g->centre_head[cell];
      for (; i >= 0; i = list == 0 ? g->body_next[i] : g->centre_next[i]) {
        if (len + 64 > cap) {
          out = realloc(out, cap *= 2);
          assert_non_null(out);
        }
        len += (size_t)snprintf(out + len, cap - len, "%c%d:%d ", list == 0 ? 'b' : 'c', cell,
                                list == 0 ? i >> g->body_shift : i);
      }
    }
  }
  for (int k = 0; k < g->num_overflow + g->num_copters; k++) {
    if (len + 64 > cap) {
      out = realloc(out, cap *= 2);
      assert_non_null(out);
    }
    len += (size_t)snprintf(out + len, cap - len, k < g->num_overflow ? "o%d " : "s%d ",
                            k < g->num_overflow ? g->overflow[k] : g->by_cell[k - g->num_overflow]);
  }
  return out;
}

static void visit_record(void *ctx, const struct nps_arena_copter *c)
{
  int *seq = ctx;
  seq[++seq[0]] = c->id;
}

/** The 6 m x 5 m arena with 10 plates per wall the copter-grid tests index (twice: updated, and fresh). */
static struct nps_arena *grid_test_arena(void)
{
  char err[256] = "";
  struct nps_arena *a = nps_arena_new_rectangle(6., 5., 10, err, sizeof err);
  assert_non_null(a);
  return a;
}

/** Give the n copters c to arena a (an update of its index) and to `fresh` indexed from scratch (emptied first):
 * the copter lists of both indexes must be the same. */
static void update_and_compare_with_fresh(struct nps_arena *a, struct nps_arena *fresh,
                                          const struct nps_arena_copter *c, int n)
{
  assert_int_equal(nps_arena_set_copters(a, c, n), 0);
  assert_int_equal(nps_arena_set_copters(fresh, c, 0), 0);
  assert_int_equal(nps_arena_set_copters(fresh, c, n), 0);
  char *got = grid_lists(a), *expected = grid_lists(fresh);
  assert_string_equal(got, expected);
  for (int i = 0; i < n; i++) {   /* the cell of the current index, also of a centre in the grid with a body out of it */
    const struct nps_arena_copter *ci = &a->copters[i];
    assert_int_equal(nps_arena_grid_indexed_cell(a->grid, ci, i), nps_arena_grid_cell(a->grid, ci->pos_m[0], ci->pos_m[1]));
  }
  free(got);
  free(expected);
}

static void copter_grid_updates_equal_a_fresh_index(void **state)
{
  (void)state;
  /* 200 steps of 60 copters moving at random (crossing cells, leaving the grid, one growing beyond a cell):
   * after each update the lists equal those of a new arena indexed from scratch; box queries visit the
   * same copters in the same order whether they scan the copters or the cells */
  struct nps_arena *a = grid_test_arena(), *fresh = grid_test_arena();
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  struct nps_arena_copter c[60];
  for (int i = 0; i < 60; i++) {
    c[i] = nps_arena_copter_make(a, i, 6. * gsl_rng_uniform(rng), 5. * gsl_rng_uniform(rng), 0.6, 0.);
  }
  int overflows = 0, moves = 0;
  for (int step = 0; step < 200; step++) {
    const int n = step < 100 ? 60 : 40;   /* fewer copters: rebuilt */
    for (int i = 0; i < n; i++) {
      c[i].pos_m[0] += 0.3 * (gsl_rng_uniform(rng) - 0.5);
      c[i].pos_m[1] += 0.3 * (gsl_rng_uniform(rng) - 0.5);
    }
    c[step % n].pos_m[0] = step % 7 == 0 ? -9. : c[step % n].pos_m[0];   /* out of the grid now and then */
    c[3].radius_m = step == 150 ? 2.5 : c[3].radius_m;                    /* a body over many cells */
    update_and_compare_with_fresh(a, fresh, c, n);
    overflows += a->grid->num_overflow;
    moves++;
    for (int q = 0; q < 5; q++) {
      const double x = 7. * gsl_rng_uniform(rng) - 0.5, y = 6. * gsl_rng_uniform(rng) - 0.5;
      const double r = 2. * gsl_rng_uniform(rng);
      int by_cells[64] = { 0 }, by_scan[64] = { 0 };
      a->grid->direct_max_copters = 0;
      nps_arena_copters_near(a, x, y, r, visit_record, by_cells);
      a->grid->direct_max_copters = 1000;
      nps_arena_copters_near(a, x, y, r, visit_record, by_scan);
      assert_memory_equal(by_cells, by_scan, sizeof by_cells);
    }
    /* the scan of every copter visits each once, in the order of a box query holding the whole swarm */
    int all[64] = { 0 }, whole[64] = { 0 };
    nps_arena_grid_copters_all(a, visit_record, all);
    a->grid->direct_max_copters = step & 1 ? 0 : 1000;
    nps_arena_grid_copters_in_box(a, -1e3, -1e3, 1e3, 1e3, visit_record, whole);
    assert_int_equal(all[0], n);
    assert_memory_equal(all, whole, sizeof all);
  }
  print_message("# %d updates, %d copters out of the grid in all\n", moves, overflows);
  assert_true(overflows > 20);
  gsl_rng_free(rng);
  nps_arena_free(a);
  nps_arena_free(fresh);
}

/** Whether copter i of a lies in the stay box of its last indexing (the next update skips it). */
static int in_stay_box(const struct nps_arena *a, const struct nps_arena_copter *c, int i)
{
  return i < a->grid->num_copters && nps_arena_grid_stays(&a->grid->stay[i], c);
}

static void copter_grid_keeps_cells_exactly_at_borders(void **state)
{
  (void)state;
  /* two copters step across each kind of cell border (of the centre, of the body box's low and high edges, of the
   * grid) along x and along y, from 1 mm off to a few ulps off and back: after each update the lists equal those
   * of a fresh index, though many updates skip the copters (their centres stay in their stay boxes) */
  struct nps_arena *a = grid_test_arena(), *fresh = grid_test_arena();
  const struct nps_arena_grid *g = a->grid;
  const double r = a->copter_radius_m + NPS_ARENA_GRID_PAD_M, cell = g->cell_m;
  const double offsets[] = { -1e-3, -1e-6, -1e-9, -1e-11, -1e-13, 0., 1e-13, 1e-11, 1e-9, 1e-6, 1e-3 };
  const int n_offsets = (int)(sizeof offsets / sizeof offsets[0]);
  struct nps_arena_copter c[2] = { nps_arena_copter_make(a, 1, 2.5, 2.5, 0.6, 0.), nps_arena_copter_make(a, 2, 4.5, 3.5, 0.6, 0.) };
  int updates = 0, skipped = 0;
  for (int axis = 0; axis < 2; axis++) {
    const double o = axis == 0 ? g->x0_m : g->y0_m, n_cells = axis == 0 ? g->nx : g->ny;
    const double borders[5] = { o + 4 * cell, o + 4 * cell + r, o + 5 * cell - r, o + r, o + n_cells * cell - r };
    for (int b = 0; b < 5; b++) {
      for (int k = 0; k < 2 * n_offsets; k++) {
        const double off = offsets[k < n_offsets ? k : 2 * n_offsets - 1 - k];   /* across and back */
        for (int ulps = -3; ulps <= 3; ulps += off == 0. ? 1 : 7) {
          const double p = ulps_from(borders[b] + off, ulps);
          c[0].pos_m[axis] = p;
          c[1].pos_m[axis] = p + cell;   /* the same border one cell on */
          skipped += in_stay_box(a, &c[0], 0) + in_stay_box(a, &c[1], 1);
          update_and_compare_with_fresh(a, fresh, c, 2);
          updates++;
        }
      }
    }
  }
  print_message("# %d updates, %d copters skipped\n", updates, skipped);
  assert_true(skipped > updates / 4);
  nps_arena_free(a);
  nps_arena_free(fresh);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(swarmlab_file_is_the_report_arena),
    cmocka_unit_test(each_bad_file_gives_its_error),
    cmocka_unit_test(a_flight_height_fits_between_floor_and_wall_top),
    cmocka_unit_test(rectangle_and_scale_from_code),
    cmocka_unit_test(code_errors_name_the_wall),
    cmocka_unit_test(clockwise_polygon_has_inward_normals),
    cmocka_unit_test(copters_are_checked),
    cmocka_unit_test(snapshot_csv_has_one_row_per_segment),
    cmocka_unit_test(hook_loads_steps_and_reports_errors),
    cmocka_unit_test(copter_grid_updates_equal_a_fresh_index),
    cmocka_unit_test(copter_grid_keeps_cells_exactly_at_borders),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
