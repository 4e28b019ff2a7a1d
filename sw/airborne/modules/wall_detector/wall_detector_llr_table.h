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
 * @file modules/wall_detector/wall_detector_llr_table.h
 * The per-reading log-likelihood ratio of a copter echo (wall_detector_reading_llr) from two tables, for a reading
 * above the sonar minimum:
 *   llr(range, d) = log(E(u) + C(z) + outlier_prob),  u = d - copter_offset + sonar_offset - range,  z = range - d / 2,
 * E the echo part (wall_detector_echo_part: the shortfall density), C the cross-talk part
 * (wall_detector_crosstalk_part: a Gaussian). Each part depends on one variable, so each is tabulated once per
 * model over +-WALL_DETECTOR_LLR_TABLE_HALF_WIDTH of its sd (v = sqrt(s^2 + r^2) for the echo, the cross-talk sd
 * for C; beyond, the part is below 1e-11 of the outlier's and counts as 0) and interpolated linearly.
 * A reading clamped to the sonar minimum has one llr per peer distance d (wall_detector_reading_llr at the minimum: a
 * survival function and two normal cdfs); a third table holds that llr itself over d in [0, ranging_max_m],
 * interpolated linearly (WALL_DETECTOR_LLR_TABLE_INTERVALS intervals); its error, |interpolated - exact|, is
 * measured at every midpoint as well. Default model: largest error 4.3e-4 on a dense grid of distances.
 *
 * Error. |log(E~ + C~ + eps) - log(E + C + eps)| <= |E~ - E| / (E + eps) + |C~ - C| / (C + eps) (to first order; the
 * parts are >= 0). Linear interpolation errs by about h^2 |f''| / 8, most at an interval's midpoint, so the table
 * measures both relative errors at every midpoint when it is built and keeps their sum (plus the parts beyond the table
 * and a float margin), or the clamped table's if larger, as error_bound. A table whose bound exceeds
 * WALL_DETECTOR_LLR_TABLE_TOLERANCE is not used (the exact llr is). Default model: error_bound 8.6e-4; the largest
 * error on a dense grid of readings and distances over the whole domain is 5.8e-4
 * (tests/c/airborne/test_wall_detector_llr_table.c). The stated bound of the llr error is 1e-3.
 *
 * Why a table, in flight. The filter needs the llr of every echo against every peer in range (up to
 * WALL_DETECTOR_MAX_PEERS = 8 per echo, 4 sonars at 20 Hz). The exact llr is computed in double: three exp, an
 * erfc and a log per peer, each a software routine of thousands of cycles on a Cortex-M4, whose FPU is single
 * precision; from the table it is two interpolations and one logf in single precision. The table is not a host
 * device: the host would afford the exact llr, the autopilot less so.
 *
 * Sharing. The tables are large (6 kB) and the same for every copter with the same model, so a process keeps a
 * few (WALL_DETECTOR_LLR_TABLES) in a static pool shared by every module instance: the host runs every copter's
 * module in one process, an autopilot one. wall_detector_llr_table_shared builds a table and is called at init
 * only, before the host's threads start; wall_detector_llr_table_find only reads, for a copter whose settings
 * changed its model later (NULL when no table of that model was built: that copter uses the exact llr).
 */

#ifndef WALL_DETECTOR_LLR_TABLE_H
#define WALL_DETECTOR_LLR_TABLE_H

#include "modules/wall_detector/wall_detector_reading.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Intervals of each part's table: 512 give an llr error below 1e-3 for the default model (5.8e-4; the error
 * falls as 1 / intervals^2) */
#define WALL_DETECTOR_LLR_TABLE_INTERVALS 512

/** Half width of each part's table in the part's sd: beyond 8 sd a Gaussian is below exp(-32) = 1.3e-14 of its
 * peak */
#define WALL_DETECTOR_LLR_TABLE_HALF_WIDTH 8.0

/** Largest llr error a table may have to be used (the llr's own float rounding is about 1e-7) */
#define WALL_DETECTOR_LLR_TABLE_TOLERANCE 1e-3f

/** Tables kept per process (models in use at once: one per copter model; more fall back to the exact llr) */
#ifndef WALL_DETECTOR_LLR_TABLES
#define WALL_DETECTOR_LLR_TABLES 2
#endif

/** One part tabulated at x_k = x0_m + k / inv_step_per_m, k = 0..WALL_DETECTOR_LLR_TABLE_INTERVALS. */
struct wall_detector_llr_part_table {
  float x0_m;            ///< abscissa of the first node [m]
  float inv_step_per_m;  ///< 1 / node spacing [1/m]
  float value[WALL_DETECTOR_LLR_TABLE_INTERVALS + 1];  ///< the part at the nodes
};

/** The tabulated llr of one model. */
struct wall_detector_llr_table {
  struct wall_detector_model model;  ///< the model the table is of
  float echo_shift_m;                ///< copter_offset_m - sonar_offset_m: u = d - echo_shift_m - range [m]
  float error_bound;                 ///< bound of |table llr - exact llr| (file comment)
  struct wall_detector_llr_part_table echo;       ///< E(u)
  struct wall_detector_llr_part_table crosstalk;  ///< C(z)
  struct wall_detector_llr_part_table clamped;    ///< llr of a clamped reading against d, over [0, ranging_max_m]
};

/** Tabulate the model of `terms` (about 2000 evaluations of the exact parts). */
extern void wall_detector_llr_table_build(struct wall_detector_llr_table *table,
    const struct wall_detector_model_terms *terms);

/**
 * The llr of a reading above the sonar minimum against a peer at peer_distance_m, from the table
 * (wall_detector_reading_llr within table->error_bound).
 */
extern float wall_detector_llr_table_llr(const struct wall_detector_llr_table *table, float range_m,
    float peer_distance_m);

/**
 * The llr of a reading clamped to the sonar minimum against a peer at peer_distance_m in [0, ranging_max_m] (nearer
 * the ends beyond), from the table (wall_detector_reading_llr within table->error_bound).
 */
extern float wall_detector_llr_table_clamped_llr(const struct wall_detector_llr_table *table, float peer_distance_m);

/**
 * The pool's table of the model of `terms`, built now in a free entry if there is none. Not thread-safe: call at
 * init only.
 * @return NULL when the pool is full or the model's table misses WALL_DETECTOR_LLR_TABLE_TOLERANCE
 */
extern const struct wall_detector_llr_table *wall_detector_llr_table_shared(
  const struct wall_detector_model_terms *terms);

/** The pool's table of a model, NULL when none was built (reads only: safe on any thread after init). */
extern const struct wall_detector_llr_table *wall_detector_llr_table_find(const struct wall_detector_model *model);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_LLR_TABLE_H */
