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
 * @file state_host.h
 * Host side of the state stand-in (state.h): points a vehicle's state at the host's flight model. Host only (the
 * host in sim/ and the tests): no module includes it, so that state.h, which they do include, needs no simulator
 * header.
 */

#ifndef STATE_HOST_H
#define STATE_HOST_H

#include "state.h"
#include "nps_finken_lag.h"

/** The state `st` follows flight model `s` when read; NULL: no flight model, its members stay as written. */
static inline void state_follow_flight_model(struct State *st, const struct nps_finken_lag_state *s,
    const double *pos_error_m)
{
  st->flight = s == NULL ? (struct StateFlightModel) { NULL, NULL, NULL, NULL, NULL }
               : (struct StateFlightModel) { s->pos_m, s->vel_mps, &s->yaw_rad, &s->yaw_rate_rps, pos_error_m };
}

#endif /* STATE_HOST_H */
