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
 * @file bench_common.h
 * Shared pieces of the C benchmark programs (tests/bench/, run by `make bench`): wall-clock timing,
 * medians of repetitions, one JSON object per figure on stdout, and copters laid out at a given density.
 *
 * Output: one line per figure, {"name": ..., "value": ..., "unit": ..., "reps": ..., "min": ..., "max": ...};
 * tools/finken/bench/programs.py reads it.
 */

#ifndef BENCH_COMMON_H
#define BENCH_COMMON_H

#include "nps_arena.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/** Most repetitions a figure may have. */
#define BENCH_MAX_REPS 64
/** Angular speed of a benchmark copter on its circle [rad/s]: 0.5 m/s on a 0.5 m radius. */
#define BENCH_CIRCLE_RATE_RAD_S 1.0
/** Radius of the circle each benchmark copter flies around its grid point [m]. */
#define BENCH_CIRCLE_RADIUS_M 0.5

/** Monotonic wall-clock time [s]. */
static inline double bench_now_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int bench_cmp_double(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/** Print one figure: the median of n repetitions v[] (sorted in place), with their spread. */
static inline void bench_report(const char *name, double *v, int n, const char *unit)
{
  qsort(v, (size_t)n, sizeof(*v), bench_cmp_double);
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  printf("{\"name\": \"%s\", \"value\": %.6g, \"unit\": \"%s\", \"reps\": %d, \"min\": %.6g, \"max\": %.6g}\n",
         name, median, unit, n, v[0], v[n - 1]);
  fflush(stdout);
}

/** Exit with a message (benchmark set-up failures only). */
static inline void bench_die(const char *what, const char *why)
{
  fprintf(stderr, "bench: %s: %s\n", what, why);
  exit(1);
}

/** The value of option `--name N` in argv, or `fallback`. */
static inline double bench_option(int argc, char **argv, const char *name, double fallback)
{
  for (int i = 1; i + 1 < argc; i++) {
    if (argv[i][0] == '-' && argv[i][1] == '-' && strcmp(argv[i] + 2, name) == 0) {
      char *end;
      const double v = strtod(argv[i + 1], &end);
      if (*end != '\0' || !isfinite(v)) {
        bench_die(argv[i], "expected a number");
      }
      return v;
    }
  }
  return fallback;
}

/** The text of option `--name TEXT` in argv, or `fallback`. */
static inline const char *bench_option_text(int argc, char **argv, const char *name, const char *fallback)
{
  for (int i = 1; i + 1 < argc; i++) {
    if (argv[i][0] == '-' && argv[i][1] == '-' && strcmp(argv[i] + 2, name) == 0) {
      return argv[i + 1];
    }
  }
  return fallback;
}

/** Repetitions from --reps, within 1 .. BENCH_MAX_REPS. */
static inline int bench_reps(int argc, char **argv, int fallback)
{
  const double reps = bench_option(argc, argv, "reps", fallback);
  return reps < 1 ? 1 : (reps > BENCH_MAX_REPS ? BENCH_MAX_REPS : (int)reps);
}

/**
 * Grid points for n copters over the bounding box of the arena's walls at rest: equal cells (area / n each,
 * columns ~ sqrt(n width / depth)), one point per cell centre, row by row. centre_m holds 2 n values.
 */
static inline void bench_grid_points(const struct nps_arena *a, int n, double *centre_m)
{
  double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
  for (int i = 0; i < a->num_walls; i++) {
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], fmin(a->walls[i].a[k], a->walls[i].b[k]));
      hi[k] = fmax(hi[k], fmax(a->walls[i].a[k], a->walls[i].b[k]));
    }
  }
  const double w = hi[0] - lo[0], d = hi[1] - lo[1];
  int cols = (int)lround(sqrt(n * w / d));
  cols = cols < 1 ? 1 : cols;
  const int rows = (n + cols - 1) / cols;
  for (int i = 0; i < n; i++) {
    centre_m[2 * i] = lo[0] + w * ((i % cols) + 0.5) / cols;
    centre_m[2 * i + 1] = lo[1] + d * ((i / cols) + 0.5) / rows;
  }
}

/**
 * Pose of copter i at time t_s: on a circle of BENCH_CIRCLE_RADIUS_M around its grid point, phase spread
 * by copter, heading along the motion; speed [m/s] in *speed_mps.
 */
static inline void bench_circle_pose(const double *centre_m, int i, double z_m, double t_s, double pos_m[3],
                                     double *yaw_rad, double *speed_mps)
{
  const double phase = BENCH_CIRCLE_RATE_RAD_S * t_s + 2.399963 * i; /* golden angle: no two copters in step */
  const double dir = i % 2 ? 1.0 : -1.0;
  pos_m[0] = centre_m[2 * i] + BENCH_CIRCLE_RADIUS_M * cos(dir * phase);
  pos_m[1] = centre_m[2 * i + 1] + BENCH_CIRCLE_RADIUS_M * sin(dir * phase);
  pos_m[2] = z_m;
  *yaw_rad = dir * phase + dir * M_PI / 2.0;
  *speed_mps = BENCH_CIRCLE_RATE_RAD_S * BENCH_CIRCLE_RADIUS_M;
}

#endif /* BENCH_COMMON_H */
