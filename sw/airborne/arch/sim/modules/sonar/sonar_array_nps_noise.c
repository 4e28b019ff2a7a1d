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
 * @file arch/sim/modules/sonar/sonar_array_nps_noise.c
 * Ground-station settings of the simulated sonar noise (see sonar_array_nps_noise.h).
 */

#include "modules/sonar/sonar_array_nps_noise.h"
#include "nps_swarm.h"

#include <math.h>

struct sonar_array_nps_noise sonar_array_nps_noise;
static struct sonar_array_nps_noise applied;

static float model_param(const char *effect, const char *param)
{
  double value;
  return nps_swarm_effect_param("sonar", effect, param, &value, false) == 0 ? (float)value : NAN;
}

static void apply_one(float wanted, float *last, const char *effect, const char *param)
{
  if (!isnan(wanted) && wanted != *last) {
    double value = wanted;
    nps_swarm_effect_param("sonar", effect, param, &value, true);
    *last = wanted;
  }
}

void sonar_array_nps_noise_init(void)
{
  sonar_array_nps_noise.rayleigh_sigma = model_param("rayleigh_short", "sigma");
  sonar_array_nps_noise.crosstalk_p = model_param("crosstalk", "p");
  applied = sonar_array_nps_noise;
}

void sonar_array_nps_noise_apply(void)
{
  apply_one(sonar_array_nps_noise.rayleigh_sigma, &applied.rayleigh_sigma, "rayleigh_short", "sigma");
  apply_one(sonar_array_nps_noise.crosstalk_p, &applied.crosstalk_p, "crosstalk", "p");
}
