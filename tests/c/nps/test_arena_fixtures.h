/*
 * Arenas shared by the arena, contact, yaw memo, wall and ray-cast tests.
 */
#ifndef TEST_ARENA_FIXTURES_H
#define TEST_ARENA_FIXTURES_H

#include "test_helpers.h"
#include "nps_arena.h"

/** The SwarmLab rectangle (3 m x 4 m) scaled by 5: 15 m x 20 m, the density of 4 copters for 100 copters. */
static inline struct nps_arena *scaled_swarmlab_arena(int segments_per_wall)
{
  char err[256] = "";
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "scaled");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 3., 4., segments_per_wall, err, sizeof err), 0);
  assert_int_equal(nps_arena_config_scale(&cfg, 5., err, sizeof err), 0);
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  return a;
}

/** The turn of turned_rectangle about the origin [rad]. */
#define TURNED_RECTANGLE_RAD 0.3

/** The 6 m x 5 m rectangle [0, 6] x [0, 5] turned by TURNED_RECTANGLE_RAD about the origin: every wall oblique to the
 * grid axes (the distance across a wall changes with both coordinates, plates of a wall have different corners in
 * both). */
static inline struct nps_arena *turned_rectangle(int segments_per_wall)
{
  char err[256] = "";
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "turned");
  assert_int_equal(nps_arena_config_rectangle(&cfg, 6., 5., segments_per_wall, err, sizeof err), 0);
  const double cs = cos(TURNED_RECTANGLE_RAD), sn = sin(TURNED_RECTANGLE_RAD);
  for (int i = 0; i < cfg.num_points; i++) {
    const double x = cfg.points[i].x_m, y = cfg.points[i].y_m;
    cfg.points[i].x_m = cs * x - sn * y;
    cfg.points[i].y_m = sn * x + cs * y;
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof err);
  nps_arena_config_free(&cfg);
  assert_non_null(a);
  return a;
}

/**
 * The SwarmLab rectangle (3 m x 4 m, 20 plates per wall) with n <= 8 copters of the default size at xy (ids 1 .. n,
 * flight height 0.6 m, all heading yaw_rad), set with nps_arena_set_copters.
 */
static inline struct nps_arena *arena_with_copters(const double xy[][2], int n, double yaw_rad)
{
  char err[256] = "";
  struct nps_arena *a = nps_arena_new_rectangle(3.0, 4.0, 20, err, sizeof err);
  assert_non_null(a);
  struct nps_arena_copter c[8];
  assert_true(n <= 8);
  for (int i = 0; i < n; i++) {
    c[i] = nps_arena_copter_make(a, i + 1, xy[i][0], xy[i][1], 0.6, yaw_rad);
  }
  assert_int_equal(nps_arena_set_copters(a, c, n), 0);
  return a;
}

#endif /* TEST_ARENA_FIXTURES_H */
