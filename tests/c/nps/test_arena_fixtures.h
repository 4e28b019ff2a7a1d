/*
 * Arenas shared by the arena, wall and ray-cast tests.
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

#endif /* TEST_ARENA_FIXTURES_H */
