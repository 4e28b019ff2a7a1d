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
 * @file test_obstacle.c
 * Interior obstacles and where copters start: an obstacle in the ray casts (sides, top, line of sight), the contacts
 * keep bodies out of it (not out of one below them), and the start poses of any simple polygon stand clear of every
 * wall, obstacle and copter by NPS_START_MARGIN, the SwarmLab's start circle as it always was, a swarm too large
 * refused with the reason.
 */

#include "test_helpers.h"
#include "nps_arena.h"
#include "nps_arena_contact.h"
#include "nps_arena_start.h"
#include "nps_raycast.h"

#include <math.h>
#include <string.h>

#define ARENA(name) "conf/arena/" name

static struct nps_arena *load(const char *path)
{
  char err[512] = "";
  struct nps_arena *a = nps_arena_load(path, err, sizeof err);
  if (a == NULL) {
    print_error("%s\n", err);
  }
  assert_non_null(a);
  return a;
}

/** The 3 m x 4 m rectangle with a table [1, 2] x [1, 1.5], 0.5 m high, given clockwise (built in code). */
static struct nps_arena *rectangle_with_table(void)
{
  char err[512] = "";
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "table");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 3., 4., 20, err, sizeof err), 0);
  static const double corners[4][2] = { { 1., 1. }, { 1., 1.5 }, { 2., 1.5 }, { 2., 1. } };
  struct nps_obstacle table = { .shape = NPS_OBSTACLE_POLYGON, .height_m = 0.5, .num_corners = 4 };
  table.corners = (double (*)[2])corners;
  cfg.obstacles = &table;
  cfg.num_obstacles = 1;
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  cfg.obstacles = NULL;   /* the table is this function's, not the configuration's */
  cfg.num_obstacles = 0;
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  return a;
}

/** The pillar (r 0.2 m at (1.1, 2.5), 3 m high): seen by a sonar's ray, over it only above its top. */
static void rays_meet_the_pillar(void **state)
{
  (void)state;
  struct nps_arena *a = load(ARENA("swarmlab_pillar.xml"));
  assert_int_equal(a->num_obstacles, 1);
  struct nps_ray_hit hit;
  const double from[3] = { 0.5, 2.5, 0.6 }, east[3] = { 1., 0., 0. };
  assert_int_equal(nps_raycast(a, from, east, 3., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_OBSTACLE);
  assert_close(hit.range_m, 0.4, 1e-9);
  assert_int_equal(hit.obstacle, 0);
  assert_close(hit.normal[0], -1., 1e-9);   /* facing the ray */
  const double grazing[3] = { 0.5, 2.71, 0.6 };   /* beside the pillar: the east wall */
  assert_int_equal(nps_raycast(a, grazing, east, 3., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_WALL);
  const double to[3] = { 2., 2.5, 0.6 };
  assert_true(nps_raycast_line_blocked(a, from, to, NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, NULL));
  nps_arena_free(a);
}

/** A table 0.5 m high: a horizontal ray at 0.6 m passes over it, a downward one hits its top, one beside it the floor;
 * its sides face out whichever way its corners were given. */
static void a_low_table_is_seen_from_above(void **state)
{
  (void)state;
  struct nps_arena *a = rectangle_with_table();
  struct nps_ray_hit hit;
  const double over[3] = { 0.5, 1.25, 0.6 }, east[3] = { 1., 0., 0. }, down[3] = { 0., 0., -1. };
  assert_int_equal(nps_raycast(a, over, east, 5., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_WALL);
  const double above[3] = { 1.5, 1.25, 0.6 }, beside[3] = { 0.5, 1.25, 0.6 };
  assert_int_equal(nps_raycast(a, above, down, 5., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_OBSTACLE);
  assert_close(hit.range_m, 0.1, 1e-12);
  assert_close(hit.normal[2], 1., 0.);
  assert_int_equal(nps_raycast(a, beside, down, 5., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_FLOOR);
  const double low[3] = { 0.5, 1.25, 0.3 };
  assert_int_equal(nps_raycast(a, low, east, 5., NPS_RAYCAST_NO_ID, NPS_RAYCAST_NO_ID, &hit), NPS_HIT_OBSTACLE);
  assert_close(hit.range_m, 0.5, 1e-9);
  assert_close(hit.normal[0], -1., 1e-12);
  nps_arena_free(a);
}

/** A copter flown into the pillar is pushed out to touch it; one over the low table is left where it is, one at its
 * height is pushed out of its nearest side. */
static void contacts_keep_bodies_out(void **state)
{
  (void)state;
  struct nps_arena *a = load(ARENA("swarmlab_pillar.xml"));
  struct nps_arena_copter c = nps_arena_copter_make(a, 1, 1.1 + 0.3, 2.5, 0.6, 0.);
  assert_int_equal(nps_arena_set_copters(a, &c, 1), 0);
  assert_int_equal(nps_arena_resolve_contacts(a, NULL), 1);
  assert_close(a->copters[0].pos_m[0], 1.1 + 0.4, 1e-12);
  assert_close(a->copters[0].pos_m[1], 2.5, 1e-12);
  nps_arena_free(a);

  a = rectangle_with_table();
  struct nps_arena_copter two[2] = { nps_arena_copter_make(a, 1, 1.2, 1.3, 0.6, 0.),
                                     nps_arena_copter_make(a, 2, 1.5, 0.9, 0.3, 0.) };
  assert_int_equal(nps_arena_set_copters(a, two, 2), 0);
  assert_int_equal(nps_arena_resolve_contacts(a, NULL), 1);
  assert_close(a->copters[0].pos_m[1], 1.3, 0.);          /* its body's bottom, 0.525 m, above the top */
  assert_close(a->copters[1].pos_m[1], 1. - 0.2, 1e-12);  /* out of the south side */
  nps_arena_free(a);
}

/**
 * Whether n copters fit in a: if so, every start at least NPS_START_MARGIN clear of the walls, the obstacles and the
 * other copters; if not, the reason says the arena is too small.
 */
static int starts_fit_clear(const struct nps_arena *a, unsigned n)
{
  double pos[64][2], yaw[64];
  char err[512] = "";
  assert_true(n <= 64);
  if (nps_arena_start_poses(a, n, pos, yaw, err, sizeof err) != 0) {
    assert_non_null(strstr(err, "is too small for"));
    return 0;
  }
  const double tol = 1e-9;
  for (unsigned v = 0; v < n; v++) {
    if (nps_arena_start_clearance(a, pos[v]) < a->copter_radius_m + NPS_START_MARGIN - tol) {
      print_error("%s: copter %u of %u at (%g, %g): clearance %g m\n", a->name, v, n, pos[v][0], pos[v][1],
                  nps_arena_start_clearance(a, pos[v]));
      fail();
    }
    for (unsigned u = 0; u < v; u++) {
      assert_true(hypot(pos[v][0] - pos[u][0], pos[v][1] - pos[u][1]) >= 2. * a->copter_radius_m + NPS_START_MARGIN - tol);
    }
  }
  return 1;
}

/**
 * The L's copters no longer bunch at its reentrant corner, nor the pillar's copters around it: up to the largest
 * swarm that fits (at least 20 in these 12 m^2 arenas), every start clear; beyond, every size refused.
 */
static void starts_clear_in_any_polygon(void **state)
{
  (void)state;
  struct nps_arena *arenas[] = {
    load(ARENA("swarmlab.xml")), load(ARENA("swarmlab_l.xml")), load(ARENA("swarmlab_pillar.xml")),
    rectangle_with_table()
  };
  for (size_t k = 0; k < sizeof arenas / sizeof arenas[0]; k++) {
    unsigned fits = 0;
    while (fits < 64 && starts_fit_clear(arenas[k], fits + 1)) {
      fits++;
    }
    print_message("# %s: up to %u copters\n", arenas[k]->name, fits);
    assert_true(fits >= 20);
    for (unsigned n = fits + 1; n <= 64; n++) {
      assert_false(starts_fit_clear(arenas[k], n));
    }
    nps_arena_free(arenas[k]);
  }
}

/** SwarmLab's 4 copters start as they always did: 0.75 m from its centre, facing outward. */
static void swarmlab_start_circle_is_unchanged(void **state)
{
  (void)state;
  struct nps_arena *a = load(ARENA("swarmlab.xml"));
  double pos[4][2], yaw[4];
  char err[512] = "";
  assert_int_equal(nps_arena_start_poses(a, 4, pos, yaw, err, sizeof err), 0);
  for (unsigned v = 0; v < 4; v++) {
    assert_close(yaw[v], M_PI / 2. * v, 0.);
    assert_close(pos[v][0], 1.5 + 0.75 * cos(yaw[v]), 0.);
    assert_close(pos[v][1], 2.0 + 0.75 * sin(yaw[v]), 0.);
  }
  nps_arena_free(a);
}

/** 50 copters do not fit in the L (12 m^2) 0.5 m apart and 0.3 m from its walls: refused, saying why. */
static void too_many_copters_are_refused(void **state)
{
  (void)state;
  struct nps_arena *a = load(ARENA("swarmlab_l.xml"));
  double pos[50][2], yaw[50];
  char err[512] = "";
  assert_int_equal(nps_arena_start_poses(a, 50, pos, yaw, err, sizeof err), -1);
  assert_non_null(strstr(err, "arena \"swarmlab_l\" is too small for 50 copters"));
  nps_arena_free(a);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(rays_meet_the_pillar),
    cmocka_unit_test(a_low_table_is_seen_from_above),
    cmocka_unit_test(contacts_keep_bodies_out),
    cmocka_unit_test(starts_clear_in_any_polygon),
    cmocka_unit_test(swarmlab_start_circle_is_unchanged),
    cmocka_unit_test(too_many_copters_are_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
