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
 * @file nps_ins_drift.c
 * Drift of a copter's position estimate (model in nps_ins_drift.h).
 */

#include "nps_ins_drift.h"
#include "nps_rng.h"

#include <gsl/gsl_randist.h>
#include <math.h>

int nps_ins_drift_init(struct nps_ins_drift *drift, const struct nps_ins_drift_params *params, uint64_t seed,
                       uint64_t vehicle)
{
  *drift = (struct nps_ins_drift) { .rng = nps_rng_stream_new(seed, vehicle, NPS_RNG_SENSOR_INS) };
  if (drift->rng == NULL) {
    return -1;
  }
  for (int axis = 0; axis < 2; axis++) {
    drift->vel_error_mps[axis] = gsl_ran_gaussian_ziggurat(drift->rng, params->sd_mps);
  }
  return 0;
}

void nps_ins_drift_step(struct nps_ins_drift *drift, const struct nps_ins_drift_params *params, double dt_s)
{
  const double a = exp(-dt_s / params->tau_s);
  const double innovation_sd = params->sd_mps * sqrt(1.0 - a * a);
  for (int axis = 0; axis < 2; axis++) {
    drift->pos_error_m[axis] += drift->vel_error_mps[axis] * dt_s;
    drift->vel_error_mps[axis] = a * drift->vel_error_mps[axis] + gsl_ran_gaussian_ziggurat(drift->rng, innovation_sd);
  }
}

void nps_ins_drift_free(struct nps_ins_drift *drift)
{
  gsl_rng_free(drift->rng);
  drift->rng = NULL;
}
