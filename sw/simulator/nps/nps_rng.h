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
 * @file nps_rng.h
 * Reproducible random streams: one GSL generator per (vehicle, sensor), all derived from one seed.
 *
 * Derivation (documented so that a run can be reproduced outside this code):
 *   h = mix64(mix64(seed) ^ mix64(a + 0x9E3779B97F4A7C15 * (b + 1)))
 *   gsl seed = (h ^ (h >> 32)) & 0xffffffff
 * where mix64 is the SplitMix64 finalizer (Steele, Lea, Flood, "Fast splittable pseudorandom number
 * generators", OOPSLA 2014), a = vehicle id and b = sensor id (NPS_RNG_SENSOR_*). The generator is
 * gsl_rng_taus2 (its seed is 32 bits wide): L'Ecuyer's maximally equidistributed combined Tausworthe generator
 * (Math. Comp. 65, 1996; period 2^88), which GSL's manual lists among the fastest simulation-quality
 * generators. Its state is 24 bytes: a swarm of 1000 copters has 6000 streams, and mt19937's 5 KB each
 * (30 MB) made every draw a cache miss. Different (vehicle, sensor) pairs give unrelated seeds; the same triple
 * always gives the same stream.
 */

#ifndef NPS_RNG_H
#define NPS_RNG_H

#include <stdint.h>
#include <gsl/gsl_rng.h>

/** Sensor ids of the range-log sensors (../shared/spec/range-log.md); a copter's ranging unit is one sensor. */
#define NPS_RNG_SENSOR_SONAR_FRONT 1u
#define NPS_RNG_SENSOR_SONAR_RIGHT 2u
#define NPS_RNG_SENSOR_SONAR_BACK  3u
#define NPS_RNG_SENSOR_SONAR_LEFT  4u
#define NPS_RNG_SENSOR_SONAR_DOWN  5u
#define NPS_RNG_SENSOR_RANGING_BASE 0x10000u
/** Sensor ids used by log replay (nps_sensor_chain_simulate): the "vehicle" is then the stream key. */
#define NPS_RNG_SENSOR_REPLAY_SONAR   0xF0000001u
#define NPS_RNG_SENSOR_REPLAY_RANGING 0xF0000002u

/** SplitMix64 finalizer: a bijective 64-bit mix (constants from Steele et al. 2014). */
uint64_t nps_rng_mix64(uint64_t x);

/** The 32-bit GSL seed of stream (vehicle, sensor) under the run seed (formula in the file comment). */
unsigned long nps_rng_stream_seed(uint64_t seed, uint64_t vehicle, uint64_t sensor);

/**
 * A new generator (gsl_rng_taus2) for stream (vehicle, sensor); free it with gsl_rng_free().
 * @return NULL when out of memory
 */
gsl_rng *nps_rng_stream_new(uint64_t seed, uint64_t vehicle, uint64_t sensor);

#endif /* NPS_RNG_H */
