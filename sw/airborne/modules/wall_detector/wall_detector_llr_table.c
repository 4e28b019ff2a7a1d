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
 * @file modules/wall_detector/wall_detector_llr_table.c
 * The tabulated llr of a copter echo and the pool of tables shared by the module instances of a process (see
 * wall_detector_llr_table.h).
 */

#include "modules/wall_detector/wall_detector_llr_table.h"

#include <math.h>
#include <string.h>

/** Largest error of a reading's computed shortfall or cross-talk offset, in float from readings and distances of a
 * few metres (two roundings of 2.4e-7 m) and the table index (2^-24 of 512 steps) [m] */
#define WALL_DETECTOR_LLR_TABLE_POSITION_ERROR_M 1e-6

/** Float rounding of the interpolation and of logf, relative (a few units of 6e-8) */
#define WALL_DETECTOR_LLR_TABLE_ROUNDING 1e-6

/** Position of node k (fractional k: between nodes) as the lookup computes it from the float origin and step. */
static double node_m(const struct wall_detector_llr_part_table *part, double k)
{
  return (double)part->x0_m + k / (double)part->inv_step_per_m;
}

/** Tabulate exact(terms, x) at the N + 1 nodes of [x0_m, x0_m + span_m] (the lookup's float origin and step). */
static void tabulate(struct wall_detector_llr_part_table *part,
                     double (*exact)(const struct wall_detector_model_terms *, double),
                     const struct wall_detector_model_terms *terms, double x0_m, double span_m)
{
  enum { N = WALL_DETECTOR_LLR_TABLE_INTERVALS };
  part->x0_m = (float)x0_m;
  part->inv_step_per_m = (float)(N / span_m);
  for (int k = 0; k <= N; k++) {
    part->value[k] = (float)exact(terms, node_m(part, k));
  }
}

/**
 * Tabulate one part over +-HALF_WIDTH sd. Returns the part's contribution to the llr error (file comment of the
 * header): the largest relative error at the midpoints, the part beyond the ends (at most the end values: the
 * tails fall), and the largest relative slope times the position error of a lookup.
 */
static double build_part(struct wall_detector_llr_part_table *part,
                         double (*exact)(const struct wall_detector_model_terms *, double),
                         const struct wall_detector_model_terms *terms, double sd_m)
{
  enum { N = WALL_DETECTOR_LLR_TABLE_INTERVALS };
  const double half_m = WALL_DETECTOR_LLR_TABLE_HALF_WIDTH * sd_m;
  const double eps = terms->model.outlier_prob;
  tabulate(part, exact, terms, -half_m, 2.0 * half_m);
  double midpoint = 0.0, slope = 0.0;
  for (int k = 0; k < N; k++) {
    const double lo = part->value[k], hi = part->value[k + 1];
    const double at_mid = exact(terms, node_m(part, k + 0.5));
    midpoint = fmax(midpoint, fabs(0.5 * (lo + hi) - at_mid) / (at_mid + eps));
    slope = fmax(slope, fabs(hi - lo) * part->inv_step_per_m / (fmin(lo, hi) + eps));
  }
  const double beyond = fmax(part->value[0], part->value[N]) / eps;
  return midpoint + beyond + slope * WALL_DETECTOR_LLR_TABLE_POSITION_ERROR_M;
}

/** The llr of a reading clamped to the sonar minimum against a peer at d_m (in float, as the filter has it). */
static double clamped_llr(const struct wall_detector_model_terms *terms, double d_m)
{
  return wall_detector_reading_llr(terms, terms->model.sonar_min_m, (float)d_m);
}

/** Tabulate the llr of a clamped reading over peer distances [0, ranging_max_m]. Returns its error: the largest
 * |interpolated - exact| at the midpoints and the largest slope times the position error of a lookup. */
static double build_clamped(struct wall_detector_llr_part_table *part, const struct wall_detector_model_terms *terms)
{
  enum { N = WALL_DETECTOR_LLR_TABLE_INTERVALS };
  tabulate(part, clamped_llr, terms, 0.0, terms->model.ranging_max_m);
  double midpoint = 0.0, slope = 0.0;
  for (int k = 0; k < N; k++) {
    const double lo = part->value[k], hi = part->value[k + 1];
    midpoint = fmax(midpoint, fabs(0.5 * (lo + hi) - clamped_llr(terms, node_m(part, k + 0.5))));
    slope = fmax(slope, fabs(hi - lo) * part->inv_step_per_m);
  }
  return midpoint + slope * WALL_DETECTOR_LLR_TABLE_POSITION_ERROR_M;
}

void wall_detector_llr_table_build(struct wall_detector_llr_table *table,
                                   const struct wall_detector_model_terms *terms)
{
  const struct wall_detector_shortfall *c = &terms->shortfall;
  table->model = terms->model;
  table->echo_shift_m = terms->model.copter_offset_m - terms->model.sonar_offset_m;
  const double error = build_part(&table->echo, wall_detector_echo_part, terms, sqrt(c->v2)) +
                       build_part(&table->crosstalk, wall_detector_crosstalk_part, terms, terms->crosstalk_sd_m) +
                       WALL_DETECTOR_LLR_TABLE_ROUNDING;
  table->error_bound = (float)fmax(error, build_clamped(&table->clamped, terms) + WALL_DETECTOR_LLR_TABLE_ROUNDING);
}

/** A part table's value at the fractional node index `at` in [0, WALL_DETECTOR_LLR_TABLE_INTERVALS]: linear between
 * the nodes. */
static float part_between(const struct wall_detector_llr_part_table *part, float at)
{
  enum { N = WALL_DETECTOR_LLR_TABLE_INTERVALS };
  const int k = at < (float)N ? (int)at : N - 1;
  const float frac = at - (float)k;
  return part->value[k] + frac * (part->value[k + 1] - part->value[k]);
}

/** Fractional node index of x_m in a part table. */
static float part_index(const struct wall_detector_llr_part_table *part, float x_m)
{
  return (x_m - part->x0_m) * part->inv_step_per_m;
}

/** A part at x_m: linear between the nodes, 0 beyond the table. */
static float part_at(const struct wall_detector_llr_part_table *part, float x_m)
{
  const float at = part_index(part, x_m);
  if (!(at >= 0.f && at < (float)WALL_DETECTOR_LLR_TABLE_INTERVALS)) {
    return 0.f;
  }
  return part_between(part, at);
}

float wall_detector_llr_table_clamped_llr(const struct wall_detector_llr_table *table, float peer_distance_m)
{
  const float at = part_index(&table->clamped, peer_distance_m);
  const float last = (float)WALL_DETECTOR_LLR_TABLE_INTERVALS;
  return part_between(&table->clamped, at > 0.f ? (at < last ? at : last) : 0.f);
}

float wall_detector_llr_table_llr(const struct wall_detector_llr_table *table, float range_m, float peer_distance_m)
{
  const float shortfall_m = peer_distance_m - table->echo_shift_m - range_m;
  const float crosstalk_offset_m = range_m - 0.5f * peer_distance_m;
  return logf(part_at(&table->echo, shortfall_m) + part_at(&table->crosstalk, crosstalk_offset_m) +
              table->model.outlier_prob);
}

/** The pool: tables built so far (at init), each used when within the tolerance. */
static struct wall_detector_llr_table pool[WALL_DETECTOR_LLR_TABLES];
static unsigned pool_nb;

/** The pool's entry of a model, usable or not; NULL when none. */
static const struct wall_detector_llr_table *pool_entry(const struct wall_detector_model *model)
{
  for (unsigned i = 0; i < pool_nb; i++) {
    if (memcmp(&pool[i].model, model, sizeof(*model)) == 0) {
      return &pool[i];
    }
  }
  return NULL;
}

/** The entry if its table is within the tolerance, else NULL. */
static const struct wall_detector_llr_table *usable(const struct wall_detector_llr_table *entry)
{
  return entry != NULL && entry->error_bound <= WALL_DETECTOR_LLR_TABLE_TOLERANCE ? entry : NULL;
}

const struct wall_detector_llr_table *wall_detector_llr_table_shared(const struct wall_detector_model_terms *terms)
{
  const struct wall_detector_llr_table *entry = pool_entry(&terms->model);
  if (entry == NULL && pool_nb < WALL_DETECTOR_LLR_TABLES) {
    /* kept even when it misses the tolerance: the next copter of this model need not build it again */
    wall_detector_llr_table_build(&pool[pool_nb], terms);
    entry = &pool[pool_nb++];
  }
  return usable(entry);
}

const struct wall_detector_llr_table *wall_detector_llr_table_find(const struct wall_detector_model *model)
{
  return usable(pool_entry(model));
}
