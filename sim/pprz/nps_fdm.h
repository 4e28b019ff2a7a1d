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
 * @file nps_fdm.h
 * Host stand-in for NPS's flight-model interface: the members of Paparazzi's struct NpsFdm that our simulated sensors read, one per vehicle.
 */

#ifndef NPS_FDM
#define NPS_FDM

#include "std.h"
#include "math/pprz_algebra_double.h"
#include "math/pprz_geodetic_double.h"

struct NpsFdm {
  double time;                          ///< simulated time [s]
  double init_dt;                       ///< step of the flight model [s]
  double curr_dt;
  bool on_ground;
  struct NedCoor_d ltpprz_pos;          ///< position, local NED [m]
  struct NedCoor_d ltpprz_ecef_vel;     ///< velocity, local NED [m/s]
  struct DoubleEulers ltpprz_to_body_eulers; ///< attitude [rad]
  struct DoubleQuat ltpprz_to_body_quat;     ///< the same attitude: local NED -> body FRD, qi scalar
  struct DoubleRates body_ecef_rotvel;  ///< body rates [rad/s]
  double agl;                           ///< height above the floor [m]
  double temperature;                   ///< air temperature [deg C]
};

/**
 * Fills vehicle `vehicle`'s NpsFdm from the host's flight model: the state its modules were given this step.
 * The host sets it (nps_fdm_set_source); nps_fdm_current calls it, so that a step costs nothing for the NpsFdm
 * when no sensor reads it (none of ours does).
 */
typedef void (*nps_fdm_source_fn)(struct NpsFdm *f, unsigned vehicle);
/** Where nps_fdm_current takes the flight model from (NULL: nowhere, the members keep what was written). */
extern void nps_fdm_set_source(nps_fdm_source_fn source);
/** The flight-model state of the vehicle the host runs now. */
extern struct NpsFdm *nps_fdm_current(void);
/** Paparazzi's NPS sensors read the global `fdm`; in the host it is the current vehicle's. */
#define fdm (*nps_fdm_current())

#endif /* NPS_FDM */
