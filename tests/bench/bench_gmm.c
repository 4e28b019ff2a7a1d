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
 * @file bench_gmm.c
 * Conditional GMM draws per second on one core, each at its own true range, as the ranging simulation
 * needs them: the O(1) alias-table method (nps_gmm_sample), the exact O(K) method (nps_gmm_sample_exact),
 * and the generator alone (gsl_rng_uniform), which bounds both.
 *
 *   bench_gmm --mixture FILE [--reps 5] [--draws 4000000] [--max-range 2.5] [--seed 1]
 *
 * True ranges: uniform on [0, max-range] (the ranging chain's range: farther peers read "no echo" before
 * the mixture is reached), a fresh one per draw from a table of 2^16, so no two draws in a row share a cell.
 */

#include "bench_common.h"
#include "nps_gmm.h"
#include "nps_rng.h"
#include "nps_sensor_model_xml.h"

#include <gsl/gsl_rng.h>

/** True ranges cycled through (a power of two). */
#define BENCH_GMM_TRUE_RANGES (1u << 16)
/** The exact method is this much slower; it gets fewer draws so each repetition takes similar time. */
#define BENCH_GMM_EXACT_FRACTION 0.02

typedef double (*bench_gmm_sampler)(const struct nps_gmm *gmm, double t_m, gsl_rng *r);

static double uniform_only(const struct nps_gmm *gmm, double t_m, gsl_rng *r)
{
  (void)gmm;
  return t_m + gsl_rng_uniform(r);
}

/** Draws per second of one repetition; the sum of the draws goes to *sink so nothing is optimised away. */
static double draws_per_s(bench_gmm_sampler sample, const struct nps_gmm *gmm, const double *true_m, long draws,
                          gsl_rng *r, double *sink)
{
  double sum = 0.0;
  const double t0 = bench_now_s();
  for (long i = 0; i < draws; i++) {
    sum += sample(gmm, true_m[i & (BENCH_GMM_TRUE_RANGES - 1)], r);
  }
  const double elapsed_s = bench_now_s() - t0;
  *sink += sum;
  return (double)draws / elapsed_s;
}

int main(int argc, char **argv)
{
  const char *path = bench_option_text(argc, argv, "mixture", NULL);
  if (path == NULL) {
    bench_die("usage", "bench_gmm --mixture FILE [--reps N] [--draws N] [--max-range M] [--seed S]");
  }
  const int reps = bench_reps(argc, argv, 5);
  const long draws = (long)bench_option(argc, argv, "draws", 4e6);
  const double max_range_m = bench_option(argc, argv, "max-range", 2.5);
  char err[512];
  struct nps_gmm *gmm = nps_sensor_model_load_mixture(path, err, sizeof(err));
  if (gmm == NULL) {
    bench_die(path, err);
  }
  gsl_rng *r = nps_rng_stream_new((uint64_t)bench_option(argc, argv, "seed", 1), 1, NPS_RNG_SENSOR_RANGING_BASE);
  double *true_m = malloc(BENCH_GMM_TRUE_RANGES * sizeof(*true_m));
  if (r == NULL || true_m == NULL) {
    bench_die("bench_gmm", "out of memory");
  }
  for (unsigned i = 0; i < BENCH_GMM_TRUE_RANGES; i++) {
    true_m[i] = max_range_m * gsl_rng_uniform(r);
  }
  double fast[BENCH_MAX_REPS], exact[BENCH_MAX_REPS], uniform[BENCH_MAX_REPS], sink = 0.0;
  const long exact_draws = (long)fmax(1000.0, BENCH_GMM_EXACT_FRACTION * (double)draws);
  draws_per_s(nps_gmm_sample, gmm, true_m, draws / 10, r, &sink); /* warm-up: caches, frequency */
  for (int k = 0; k < reps; k++) {
    fast[k] = draws_per_s(nps_gmm_sample, gmm, true_m, draws, r, &sink);
    exact[k] = draws_per_s(nps_gmm_sample_exact, gmm, true_m, exact_draws, r, &sink);
    uniform[k] = draws_per_s(uniform_only, gmm, true_m, draws, r, &sink);
  }
  bench_report("gmm_draws_per_s", fast, reps, "1/s");
  bench_report("gmm_exact_draws_per_s", exact, reps, "1/s");
  bench_report("rng_uniform_per_s", uniform, reps, "1/s");
  fprintf(stderr, "bench_gmm: K = %zu, checksum %.6g\n", nps_gmm_size(gmm), sink);
  free(true_m);
  gsl_rng_free(r);
  nps_gmm_free(gmm);
  return 0;
}
