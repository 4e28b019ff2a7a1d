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
 * @file state.h
 * Host stand-in for Paparazzi's state interface: the float getters our modules use, per simulated vehicle.
 */

#ifndef STATE_H
#define STATE_H

#include "std.h"
#include "math/pprz_algebra_float.h"
#include "math/pprz_geodetic_float.h"

#include <math.h>

/**
 * Where the host's flight model keeps a vehicle's motion (doubles): the state's members follow it when read. The host
 * points it at its flight model (state_host.h; this header knows no simulator type, so that the modules including it
 * build for an autopilot too). All NULL: no flight model.
 */
struct StateFlightModel {
  const double *pos_m;        ///< position, ENU [m] (3 values)
  const double *vel_mps;      ///< velocity, ENU [m/s] (3 values)
  const double *yaw_rad;      ///< heading, from east toward north [rad]
  const double *yaw_rate_rps; ///< heading rate [rad/s]
  const double *pos_error_m;  ///< the position estimate's error, ENU [m] (3 values; NULL: none), nps_ins_drift.h
};

/**
 * The subset of Paparazzi's struct State our modules read (same member names). The host points each vehicle's state at
 * its flight model (ENU, doubles), and a getter derives its member from it when read, as Paparazzi's state interface
 * converts a representation on demand: most copter-steps read none. Without a flight model (tests) the members are
 * as written, and the NED position and speed follow from the ENU ones (an exact swap and sign change).
 */
struct State {
  struct NedCoor_f ned_pos_f;          ///< position in the local NED frame [m] (from enu_pos_f when read)
  struct EnuCoor_f enu_pos_f;          ///< position in the local ENU frame [m]
  struct NedCoor_f ned_speed_f;        ///< ground speed, NED [m/s] (from enu_speed_f when read)
  struct EnuCoor_f enu_speed_f;        ///< ground speed, ENU [m/s]
  struct FloatEulers ned_to_body_eulers_f; ///< attitude [rad], psi from north toward east
  struct FloatRates body_rates_f;      ///< body rates [rad/s]
  struct StateFlightModel flight;      ///< the host's flight model the members follow when read
};

/** The state of the vehicle the host runs now. */
extern struct State *state_current(void);

/** NED from ENU: north = y, east = x, down = -z (exact in floating point). */
static inline void state_ned_of_enu(struct NedCoor_f *ned, const struct EnuCoor_f *enu)
{
  *ned = (struct NedCoor_f) { enu->y, enu->x, -enu->z };
}

/** An ENU member of the state, brought to the flight model's double vector flight_v (NULL: no flight model, the
 * member stays as written); returns the member. */
static inline struct EnuCoor_f *state_enu_follow(struct EnuCoor_f *enu, const double *flight_v)
{
  if (flight_v != NULL) {
    *enu = (struct EnuCoor_f) { (float)flight_v[0], (float)flight_v[1], (float)flight_v[2] };
  }
  return enu;
}

static inline struct EnuCoor_f *stateGetPositionEnu_f(void)
{
  struct State *st = state_current();
  struct EnuCoor_f *pos = state_enu_follow(&st->enu_pos_f, st->flight.pos_m);
  const double *error_m = st->flight.pos_error_m;
  if (error_m != NULL) {  /* the estimate: the flight model's position and the INS's error */
    *pos = (struct EnuCoor_f) { (float)(st->flight.pos_m[0] + error_m[0]), (float)(st->flight.pos_m[1] + error_m[1]),
                                (float)(st->flight.pos_m[2] + error_m[2]) };
  }
  return pos;
}
static inline struct NedCoor_f *stateGetPositionNed_f(void)
{
  struct State *st = state_current();
  state_ned_of_enu(&st->ned_pos_f, stateGetPositionEnu_f());
  return &st->ned_pos_f;
}
static inline struct EnuCoor_f *stateGetSpeedEnu_f(void)
{
  struct State *st = state_current();
  return state_enu_follow(&st->enu_speed_f, st->flight.vel_mps);
}
static inline struct NedCoor_f *stateGetSpeedNed_f(void)
{
  struct State *st = state_current();
  state_ned_of_enu(&st->ned_speed_f, stateGetSpeedEnu_f());
  return &st->ned_speed_f;
}
/** Attitude: level; heading psi from north toward east = pi/2 - the flight model's yaw from east toward north. */
static inline struct FloatEulers *stateGetNedToBodyEulers_f(void)
{
  struct State *st = state_current();
  if (st->flight.yaw_rad != NULL) {
    st->ned_to_body_eulers_f = (struct FloatEulers) { 0.0f, 0.0f, (float)(M_PI / 2.0 - *st->flight.yaw_rad) };
  }
  return &st->ned_to_body_eulers_f;
}
/** Body rates: about the vertical only, r = - the yaw rate (yaw from east toward north, psi from north toward east). */
static inline struct FloatRates *stateGetBodyRates_f(void)
{
  struct State *st = state_current();
  if (st->flight.yaw_rate_rps != NULL) {
    st->body_rates_f = (struct FloatRates) { 0.0f, 0.0f, (float)-*st->flight.yaw_rate_rps };
  }
  return &st->body_rates_f;
}

#endif /* STATE_H */
