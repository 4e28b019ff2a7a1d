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
 * @file nps_rng.c
 * Reproducible random streams per (vehicle, sensor); see nps_rng.h for the seed derivation.
 */

#include "nps_rng.h"


/** Golden-ratio increment of SplitMix64 (2^64 / phi), Steele et al. 2014. */
#define NPS_RNG_GOLDEN 0x9E3779B97F4A7C15ull

uint64_t nps_rng_mix64(uint64_t x)
{
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

unsigned long nps_rng_stream_seed(uint64_t seed, uint64_t vehicle, uint64_t sensor)
{
  uint64_t h = nps_rng_mix64(nps_rng_mix64(seed) ^ nps_rng_mix64(vehicle + NPS_RNG_GOLDEN * (sensor + 1)));
  return (unsigned long)((h ^ (h >> 32)) & 0xffffffffull);
}

gsl_rng *nps_rng_stream_new(uint64_t seed, uint64_t vehicle, uint64_t sensor)
{
  gsl_rng *r = gsl_rng_alloc(gsl_rng_taus2);
  if (r != NULL) {
    gsl_rng_set(r, nps_rng_stream_seed(seed, vehicle, sensor));
  }
  return r;
}
