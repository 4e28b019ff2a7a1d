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
 * @file nps_fdm_finken.h
 * What fdm_finken offers besides NPS's flight-model interface (nps_fdm.h).
 */

#ifndef NPS_FDM_FINKEN_H
#define NPS_FDM_FINKEN_H

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Put the copter at rest on the ground, north_m and east_m [m] of the flight plan's origin, heading heading_rad
 * (from north toward east). nps_fdm_init places it at NPS_FINKEN_START_*; finken_world moves each aircraft of a
 * swarm to its start in the arena before the first step.
 */
extern void nps_fdm_finken_place(double north_m, double east_m, double heading_rad);

/**
 * A contact in the arena (a wall, another copter) moved the copter to north_m, east_m [m] of the flight plan's
 * origin: the flight model takes that position and stops its motion into the push (nps_arena_contact_take), as
 * our host's flight models do; finken_world calls it after each arena step that pushed this copter.
 */
extern void nps_fdm_finken_take_contact(double north_m, double east_m);

#ifdef __cplusplus
}
#endif

#endif /* NPS_FDM_FINKEN_H */
