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
 * @file test_floor.c
 * Floor materials: names and codes, the material under a point, the <floor> element of the arena XML (a good file
 * and every bad case with its file:line and reason), floors built in code, and the segment-through-box test the
 * inside-the-polygon check rests on.
 */
#include "test_helpers.h"
#include "nps_arena.h"
#include "nps_floor.h"
#include "nps_geometry.h"

#include <stdlib.h>
#include <string.h>

#define DATA(name) "tests/data/arena/" name

static void materials_have_fixed_codes_ordered_by_absorption(void **state)
{
  (void)state;
  assert_int_equal(nps_floor_material_from_name("hard"), 1);
  assert_int_equal(nps_floor_material_from_name("carpet"), 2);
  assert_int_equal(nps_floor_material_from_name("foam"), 3);
  assert_int_equal(nps_floor_material_from_name("none"), NPS_FLOOR_NONE);   /* not a material a file may name */
  assert_int_equal(nps_floor_material_from_name("Foam"), NPS_FLOOR_NONE);
  assert_int_equal(nps_floor_material_from_name(""), NPS_FLOOR_NONE);
  assert_int_equal(nps_floor_material_from_name(NULL), NPS_FLOOR_NONE);
  assert_string_equal(nps_floor_material_name(NPS_FLOOR_CARPET), "carpet");
  assert_string_equal(nps_floor_material_name((enum nps_floor_material)7), "none");
}

static void the_material_at_a_point_is_its_region_s_or_the_default(void **state)
{
  (void)state;
  struct nps_floor_region regions[2] = {
    { .x0_m = 0., .y0_m = 0., .x1_m = 1.5, .y1_m = 4., .material = NPS_FLOOR_FOAM },
    { .x0_m = 1.5, .y0_m = 3., .x1_m = 3., .y1_m = 4., .material = NPS_FLOOR_CARPET },
  };
  struct nps_floor f;
  nps_floor_init(&f);
  assert_int_equal(nps_floor_material_at(&f, 1., 1.), NPS_FLOOR_HARD);          /* no regions: the default */
  f.regions = regions;
  f.num_regions = 2;
  assert_int_equal(nps_floor_material_at(&f, 0.7, 2.), NPS_FLOOR_FOAM);
  assert_int_equal(nps_floor_material_at(&f, 2., 3.5), NPS_FLOOR_CARPET);
  assert_int_equal(nps_floor_material_at(&f, 2., 2.9), NPS_FLOOR_HARD);
  assert_int_equal(nps_floor_material_at(&f, 1.5, 3.5), NPS_FLOOR_FOAM);        /* a shared border: the first region */
  assert_int_equal(nps_floor_material_at(&f, 3., 3.), NPS_FLOOR_CARPET);        /* borders are part of a region */
  assert_int_equal(nps_floor_material_at(&f, ulps_from(3., 1), 3.), NPS_FLOOR_HARD);
  f.default_material = NPS_FLOOR_CARPET;
  assert_int_equal(nps_floor_material_at(&f, 2., 1.), NPS_FLOOR_CARPET);
}

static void a_floor_file_is_read_with_its_regions(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena *a = nps_arena_load(DATA("floor_mat.xml"), err, sizeof err);
  if (!a) {
    print_error("%s\n", err);
  }
  assert_non_null(a);
  assert_int_equal(a->floor.default_material, NPS_FLOOR_HARD);
  assert_int_equal(a->floor.num_regions, 2);
  assert_int_equal(a->floor.regions[0].material, NPS_FLOOR_FOAM);
  assert_int_equal(a->floor.regions[0].line, 12);
  assert_close(a->floor.regions[0].x1_m, 1.5, 0.);
  assert_int_equal(a->floor.regions[1].material, NPS_FLOOR_CARPET);
  assert_close(a->floor.regions[1].y0_m, 3., 0.);
  assert_int_equal(nps_floor_material_at(&a->floor, 1., 1.), NPS_FLOOR_FOAM);
  assert_int_equal(nps_floor_material_at(&a->floor, 2., 1.), NPS_FLOOR_HARD);
  nps_arena_free(a);
}

static void an_arena_without_floor_is_hard_everywhere(void **state)
{
  (void)state;
  char err[512] = "";
  struct nps_arena *a = nps_arena_load("conf/arena/swarmlab.xml", err, sizeof err);
  assert_non_null(a);
  assert_int_equal(a->floor.default_material, NPS_FLOOR_HARD);
  assert_int_equal(a->floor.num_regions, 0);
  assert_int_equal(nps_floor_material_at(&a->floor, 1.5, 2.), NPS_FLOOR_HARD);
  nps_arena_free(a);
}

struct bad_case {
  const char *file;
  int line;
  const char *reason;
};

static const struct bad_case bad_cases[] = {
  { DATA("floor_unknown_material.xml"), 12, "<region> material=\"grass\": unknown floor material (expected hard, carpet or foam)" },
  { DATA("floor_unknown_default.xml"), 11, "<floor> material=\"ice\": unknown floor material (expected hard, carpet or foam)" },
  { DATA("floor_no_material.xml"), 12, "<region> needs a 'material' attribute (hard, carpet or foam)" },
  { DATA("floor_missing_corner.xml"), 12, "<region> needs a 'y1' attribute" },
  { DATA("floor_overlap.xml"), 13, "<region> overlaps the <region> of line 12 on (1, 1)-(1.5, 1.5)" },
  { DATA("floor_outside.xml"), 12, "<region> (2, 1)-(3.5, 2) reaches outside the arena polygon" },
  { DATA("floor_notch.xml"), 16, "<region> (0.5, 3)-(2.5, 3.5) reaches outside the arena polygon" },
  { DATA("floor_empty_region.xml"), 12, "<region> (2, 1)-(1, 2): expected x0 < x1 and y0 < y1 [m]" },
  { DATA("floor_unknown_element.xml"), 12, "unknown element <circle> in <floor> (expected <region>)" },
  { DATA("floor_twice.xml"), 12, "<floor> is given twice (first at line 11)" },
  { DATA("floor_unknown_attribute.xml"), 12, "unknown attribute 'height' on <region>" },
};

static void each_bad_floor_gives_its_line_and_reason(void **state)
{
  (void)state;
  for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
    const struct bad_case *c = &bad_cases[i];
    char err[512] = "", expected[600];
    snprintf(expected, sizeof expected, "%s:%d: %s", c->file, c->line, c->reason);
    struct nps_arena *a = nps_arena_load(c->file, err, sizeof err);
    if (a || strcmp(err, expected) != 0) {
      print_error("got:      %s\nexpected: %s\n", err, expected);
      nps_arena_free(a);
      fail();
    }
  }
}

/** A configuration built in code: the U-shaped arena of floor_notch.xml with one region. */
static int check_u_arena_region(double x0, double y0, double x1, double y1, enum nps_floor_material m, char *err,
                                size_t err_len)
{
  static const double u[9][2] = { { 0, 0 }, { 3, 0 }, { 3, 4 }, { 2, 4 }, { 2, 1 }, { 1, 1 }, { 1, 4 }, { 0, 4 }, { 0, 0 } };
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "u arena");
  cfg.num_points = 9;
  cfg.points = calloc(9, sizeof * cfg.points);
  cfg.walls = calloc(8, sizeof * cfg.walls);
  cfg.floor.regions = calloc(1, sizeof * cfg.floor.regions);
  assert_true(cfg.points && cfg.walls && cfg.floor.regions);
  for (int i = 0; i < 9; i++) {
    cfg.points[i].x_m = u[i][0];
    cfg.points[i].y_m = u[i][1];
  }
  for (int i = 0; i < 8; i++) {
    nps_wall_params_default(&cfg.walls[i]);
  }
  cfg.floor.num_regions = 1;
  cfg.floor.regions[0] = (struct nps_floor_region) { .x0_m = x0, .y0_m = y0, .x1_m = x1, .y1_m = y1, .material = m };
  const int rc = nps_arena_config_check(&cfg, err, err_len);
  nps_arena_config_free(&cfg);
  return rc;
}

static void a_region_may_fill_an_arm_but_not_cross_the_notch(void **state)
{
  (void)state;
  char err[512] = "";
  assert_int_equal(check_u_arena_region(0., 0., 1., 4., NPS_FLOOR_FOAM, err, sizeof err), 0);    /* the left arm */
  assert_int_equal(check_u_arena_region(0., 0., 3., 1., NPS_FLOOR_FOAM, err, sizeof err), 0);    /* the base */
  assert_int_equal(check_u_arena_region(0.5, 0.5, 2.5, 1.5, NPS_FLOOR_FOAM, err, sizeof err), -1);
  assert_string_equal(err, "u arena: <region> (0.5, 0.5)-(2.5, 1.5) reaches outside the arena polygon");
  assert_int_equal(check_u_arena_region(1.2, 2., 1.8, 3., NPS_FLOOR_FOAM, err, sizeof err), -1);  /* in the notch */
  assert_int_equal(check_u_arena_region(0., 0., 1., NAN, NPS_FLOOR_FOAM, err, sizeof err), -1);
  assert_string_equal(err, "u arena: <region> (0, 0)-(1, nan): expected x0 < x1 and y0 < y1 [m]");
  assert_int_equal(check_u_arena_region(0., 0., 1., 1., NPS_FLOOR_NONE, err, sizeof err), -1);
  assert_string_equal(err, "u arena: <region> material code 0: expected a floor material (hard, carpet or foam)");
}

static void a_segment_enters_a_box_only_through_its_inside(void **state)
{
  (void)state;
  const double lo[2] = { 0., 0. }, hi[2] = { 1., 1. };
  const double a[2] = { -1., 0.5 }, b[2] = { 2., 0.5 };         /* straight through */
  const double c[2] = { -1., 0. }, d[2] = { 2., 0. };           /* along the bottom border */
  const double e[2] = { -1., 1. }, f[2] = { 1., -1. };          /* through the corner (0, 0) only */
  const double g[2] = { 0.2, 0.2 }, h[2] = { 0.3, 0.4 };        /* wholly inside */
  const double i[2] = { 1.5, 0.5 }, j[2] = { 3., 0.5 };         /* outside */
  const double k[2] = { -1., 1. }, l[2] = { 1., -0.9999 };       /* just inside the corner: cuts a sliver */
  assert_true(nps_geometry_segment_enters_box(a, b, lo, hi));
  assert_false(nps_geometry_segment_enters_box(c, d, lo, hi));
  assert_false(nps_geometry_segment_enters_box(e, f, lo, hi));
  assert_true(nps_geometry_segment_enters_box(g, h, lo, hi));
  assert_false(nps_geometry_segment_enters_box(i, j, lo, hi));
  assert_true(nps_geometry_segment_enters_box(k, l, lo, hi));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(materials_have_fixed_codes_ordered_by_absorption),
    cmocka_unit_test(the_material_at_a_point_is_its_region_s_or_the_default),
    cmocka_unit_test(a_floor_file_is_read_with_its_regions),
    cmocka_unit_test(an_arena_without_floor_is_hard_everywhere),
    cmocka_unit_test(each_bad_floor_gives_its_line_and_reason),
    cmocka_unit_test(a_region_may_fill_an_arm_but_not_cross_the_notch),
    cmocka_unit_test(a_segment_enters_a_box_only_through_its_inside),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
