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

/**
 * The subset of Paparazzi's struct State the host fills from the flight model (same member names). The host sets
 * the ENU position and speed; the NED ones are derived from them when read (as Paparazzi's state interface converts
 * a representation on demand), an exact swap of x and y and change of sign of z: most copter-steps read neither.
 */
struct State {
  struct NedCoor_f ned_pos_f;          ///< position in the local NED frame [m] (from enu_pos_f when read)
  struct EnuCoor_f enu_pos_f;          ///< position in the local ENU frame [m]
  struct NedCoor_f ned_speed_f;        ///< ground speed, NED [m/s] (from enu_speed_f when read)
  struct EnuCoor_f enu_speed_f;        ///< ground speed, ENU [m/s]
  struct FloatEulers ned_to_body_eulers_f; ///< attitude [rad], psi from north toward east
  struct FloatRates body_rates_f;      ///< body rates [rad/s]
};

/** The state of the vehicle the host runs now. */
extern struct State *state_current(void);

/** NED from ENU: north = y, east = x, down = -z (exact in floating point). */
static inline void state_ned_of_enu(struct NedCoor_f *ned, const struct EnuCoor_f *enu)
{
  *ned = (struct NedCoor_f) { enu->y, enu->x, -enu->z };
}

static inline struct NedCoor_f *stateGetPositionNed_f(void)
{
  struct State *st = state_current();
  state_ned_of_enu(&st->ned_pos_f, &st->enu_pos_f);
  return &st->ned_pos_f;
}
static inline struct EnuCoor_f *stateGetPositionEnu_f(void) { return &state_current()->enu_pos_f; }
static inline struct NedCoor_f *stateGetSpeedNed_f(void)
{
  struct State *st = state_current();
  state_ned_of_enu(&st->ned_speed_f, &st->enu_speed_f);
  return &st->ned_speed_f;
}
static inline struct EnuCoor_f *stateGetSpeedEnu_f(void) { return &state_current()->enu_speed_f; }
static inline struct FloatEulers *stateGetNedToBodyEulers_f(void) { return &state_current()->ned_to_body_eulers_f; }
static inline struct FloatRates *stateGetBodyRates_f(void) { return &state_current()->body_rates_f; }

#endif /* STATE_H */
