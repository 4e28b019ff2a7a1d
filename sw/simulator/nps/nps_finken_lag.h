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
 * @file nps_finken_lag.h
 * Flight model of a FINken for the NPS-style host: altitude hold and first-order response to
 * velocity and heading commands (the FINken flies at a fixed height in the arena, report section 2.1).
 * (Paparazzi's own NPS flies the rigid-body model nps_finken_quadrotor.h through nps_fdm_finken.c.)
 *
 * Arena frame ENU: x east, y north, z up [m]; yaw from x toward y [rad].
 */

#ifndef NPS_FINKEN_LAG_H
#define NPS_FINKEN_LAG_H

struct nps_finken_lag_params {
  double velocity_tau_s;   ///< time constant of the horizontal velocity response [s]
  double yaw_tau_s;        ///< time constant of the heading response [s]
  double altitude_m;       ///< altitude held [m]
  double altitude_tau_s;   ///< time constant of the altitude response [s]
  double max_speed_mps;    ///< horizontal speed command limit [m/s]
};

/** Fraction of the remaining error each first-order lag removes in one step of dt_s: 1 - exp(-dt / tau). */
struct nps_finken_lag_gains {
  double dt_s;             ///< the step these gains are for [s]
  double per_step_hz;      ///< 1 / dt_s, turning a step's change into a rate [1/s]
  double velocity;         ///< horizontal velocity lag
  double altitude;         ///< altitude lag
  double yaw;              ///< heading lag
};

/**
 * The last speed limit (a hypot) of a command that holds for several steps, reused only when the new inputs are
 * bit for bit the same (so the result is exactly that of a recomputation). All zero is a valid entry.
 */
struct nps_finken_lag_memo {
  double vx_cmd_mps, vy_cmd_mps, max_speed_mps; ///< speed-limit inputs [m/s]
  double vx_limited_mps, vy_limited_mps; ///< its result [m/s]
};

struct nps_finken_lag_state {
  double pos_m[3];         ///< position, ENU [m]
  double vel_mps[3];       ///< velocity, ENU [m/s]
  double yaw_rad;          ///< heading, from x (east) toward y (north) [rad]
  double yaw_rate_rps;     ///< heading rate [rad/s]
  struct nps_finken_lag_memo memo; ///< cache of the last step (no effect on any result)
};

/** Gains of the three lags of p for steps of dt_s seconds (a host with a fixed step computes them once). */
extern void nps_finken_lag_gains_init(struct nps_finken_lag_gains *g, const struct nps_finken_lag_params *p,
                                      double dt_s);

/** nps_finken_lag_step with the gains of its step computed beforehand (the same results, bit for bit). */
extern void nps_finken_lag_advance(struct nps_finken_lag_state *s, const struct nps_finken_lag_params *p,
                                   const struct nps_finken_lag_gains *g, double vx_cmd_mps, double vy_cmd_mps,
                                   double yaw_cmd_rad);

/**
 * Advance one step of dt_s seconds toward the commanded ENU velocity and yaw.
 * Each first-order lag x' = (x_cmd - x) / tau is integrated exactly over the step:
 * x += (x_cmd - x) * (1 - exp(-dt / tau)), so any dt is stable.
 */
extern void nps_finken_lag_step(struct nps_finken_lag_state *s, const struct nps_finken_lag_params *p,
                                double vx_cmd_mps, double vy_cmd_mps, double yaw_cmd_rad, double dt_s);

/**
 * A contact moved the copter to pos_m (x, y; z unchanged): take that position and stop the motion into whatever
 * pushed it back (nps_arena_contact_take: a velocity into the push loses its part along it).
 */
extern void nps_finken_lag_take_contact(struct nps_finken_lag_state *s, const double pos_m[2]);

#endif /* NPS_FINKEN_LAG_H */
