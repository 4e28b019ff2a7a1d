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
 * @file nps_ins_drift.h
 * Drift of a copter's position estimate, as an INS without absolute position fixes has it (our host's
 * `--ins-drift`; Paparazzi's own NPS runs its real INS instead).
 *
 * The model: the estimate's velocity error is a first-order Gauss-Markov process per horizontal axis, and the
 * position error its integral (the usual error model of a velocity-aided INS, e.g. optical flow: Groves,
 * "Principles of GNSS, Inertial, and Multisensor Integrated Navigation Systems", 2nd ed., 2013, sections 14.2.6
 * and 16.3.2):
 *   v(t + dt) = a v(t) + sd sqrt(1 - a^2) w,  a = exp(-dt / tau),  w ~ N(0, 1)   (exact for a Gauss-Markov process)
 *   e(t + dt) = e(t) + v(t) dt
 * v starts from its stationary law N(0, sd^2) and e from 0. Over times much longer than tau the position error
 * is a random walk of diffusion 2 sd^2 tau per axis: with sd = 0.02 m/s and tau = 10 s, 1.2 m (one sd) after
 * 180 s, about 2 cm/s at any moment. Each copter has its own stream (nps_rng, sensor NPS_RNG_SENSOR_INS).
 */

#ifndef NPS_INS_DRIFT_H
#define NPS_INS_DRIFT_H

#include <gsl/gsl_rng.h>
#include <stdint.h>

/** Sensor id of the INS drift streams (nps_rng.h). */
#define NPS_RNG_SENSOR_INS 0x20000u

/** Parameters of the drift (sd 0: no drift). */
struct nps_ins_drift_params {
  double sd_mps;   ///< stationary sd of the velocity error per axis [m/s], >= 0
  double tau_s;    ///< its correlation time [s], > 0
};

/** The drift of one copter's estimate. */
struct nps_ins_drift {
  double vel_error_mps[2];  ///< velocity error, east and north [m/s]
  double pos_error_m[3];    ///< position error, east, north and up (up stays 0) [m]
  gsl_rng *rng;             ///< its own stream
};

/** Start the drift of copter `vehicle` under run seed `seed`; -1 when out of memory. */
extern int nps_ins_drift_init(struct nps_ins_drift *drift, const struct nps_ins_drift_params *params, uint64_t seed,
                              uint64_t vehicle);

/** Advance the drift by dt_s. */
extern void nps_ins_drift_step(struct nps_ins_drift *drift, const struct nps_ins_drift_params *params, double dt_s);

/** Free its stream. */
extern void nps_ins_drift_free(struct nps_ins_drift *drift);

#endif /* NPS_INS_DRIFT_H */
