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
 * @file bench_walls.c
 * Cost of one wall step at 100 Hz: nps_arena_set_copters (copy and re-index the copters) plus
 * nps_arena_walls_step (nearest copter per plate, PID and hinge dynamics of the plates that move), i.e. what
 * the host's nps_swarm_step does every step apart from the snapshot file.
 *
 *   bench_walls [--reps 5] [--seconds 60]
 *
 * Scenes (rectangles built in code; copters on a grid at the density of 4 in 3 m x 4 m, each flying a
 * 0.5 m circle, so the outer ones drive the plates of the nearest wall):
 *   wall_step_us_4x20       4 copters, SwarmLab 3 m x 4 m, 20 plates per wall (80 plates)
 *   wall_step_us_1000x100   1000 plates (250 per wall) on 15 m x 20 m, 100 copters
 *   wall_step_us_4000x1000  4000 plates (1000 per wall) on 47.4 m x 63.2 m, 1000 copters
 */

#include "bench_common.h"
#include "nps_walls.h"

/** Simulation rate of the wall steps [Hz] (the example airframe's PERIODIC_FREQUENCY). */
#define BENCH_WALLS_RATE_HZ 100.0

struct walls_scene {
  const char *name;
  int copters;
  int plates_per_wall;
};

static struct nps_arena *scene_arena(const struct walls_scene *s)
{
  char err[512];
  struct nps_arena_config cfg;
  nps_arena_config_init(&cfg, "bench_walls");
  /* SwarmLab's 3 m x 4 m, scaled for the same floor area per copter (3 m^2) */
  if (nps_arena_config_rectangle(&cfg, 3.0, 4.0, s->plates_per_wall, err, sizeof(err)) != 0 ||
      nps_arena_config_scale(&cfg, sqrt(s->copters / 4.0), err, sizeof(err)) != 0) {
    bench_die(s->name, err);
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, sizeof(err));
  nps_arena_config_free(&cfg);
  if (a == NULL) {
    bench_die(s->name, err);
  }
  return a;
}

/** Mean cost of one step [us] over `seconds` of simulated time. */
static double step_us(struct nps_arena *a, const double *centre_m, struct nps_arena_copter *c, int n,
                      double seconds)
{
  const long steps = (long)(seconds * BENCH_WALLS_RATE_HZ);
  double busy_s = 0.0;
  for (long k = 0; k < steps; k++) {
    const double t_s = a->time_s + 1.0 / BENCH_WALLS_RATE_HZ;
    for (int i = 0; i < n; i++) {
      double speed_mps;
      bench_circle_pose(centre_m, i, a->flight_height_m, t_s, c[i].pos_m, &c[i].yaw_rad, &speed_mps);
    }
    const double t0 = bench_now_s();
    if (nps_arena_set_copters(a, c, n) != 0 || nps_arena_walls_step(a, t_s) != 0) {
      bench_die("bench_walls", "step failed");
    }
    busy_s += bench_now_s() - t0;
  }
  return 1e6 * busy_s / (double)steps;
}

int main(int argc, char **argv)
{
  static const struct walls_scene scenes[] = {
    { "wall_step_us_4x20", 4, 20 },
    { "wall_step_us_1000x100", 100, 250 },
    { "wall_step_us_4000x1000", 1000, 1000 },
  };
  const int reps = bench_reps(argc, argv, 5);
  const double seconds = bench_option(argc, argv, "seconds", 60.0);
  for (size_t s = 0; s < sizeof(scenes) / sizeof(scenes[0]); s++) {
    struct nps_arena *a = scene_arena(&scenes[s]);
    const int n = scenes[s].copters;
    double *centre_m = malloc(2 * (size_t)n * sizeof(*centre_m));
    struct nps_arena_copter *c = malloc((size_t)n * sizeof(*c));
    if (centre_m == NULL || c == NULL) {
      bench_die(scenes[s].name, "out of memory");
    }
    bench_grid_points(a, n, centre_m);
    for (int i = 0; i < n; i++) {
      c[i] = nps_arena_copter_make(a, i + 1, centre_m[2 * i], centre_m[2 * i + 1], a->flight_height_m, 0.0);
    }
    /* the heavier scenes simulate less time per repetition, so each takes about as long */
    const double scene_seconds = seconds * fmin(1.0, 4.0 / sqrt((double)n));
    step_us(a, centre_m, c, n, 0.1 * scene_seconds); /* warm-up, and plates already moving */
    double us[BENCH_MAX_REPS];
    for (int k = 0; k < reps; k++) {
      us[k] = step_us(a, centre_m, c, n, scene_seconds);
    }
    bench_report(scenes[s].name, us, reps, "us");
    int driven = 0;
    for (int i = 0; i < a->num_segments; i++) {
      driven += a->segs[i].driven;
    }
    fprintf(stderr, "bench_walls: %s: %d copters, %d plates, %d driven at the end\n", scenes[s].name, n,
            a->num_segments, driven);
    free(c);
    free(centre_m);
    nps_arena_free(a);
  }
  return 0;
}
