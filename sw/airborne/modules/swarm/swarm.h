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
 * @file modules/swarm/swarm.h
 * Paparazzi module: the FINken attraction-repulsion swarm on the horizontal sonars.
 *
 * Input (ABI): WALL_DETECTION from the wall_detector module (every horizontal sonar reading with its class).
 * Output: autopilot_guided_move_ned() at the periodic rate, heading held.
 * The law is swarm_force.c; this file only binds it.
 */

#ifndef SWARM_H
#define SWARM_H

#include "modules/core/abi.h"
#include "modules/multi_vehicle/vehicle_local.h"
#include "modules/swarm/swarm_force.h"
#include "modules/wall_detector/wall_detector_filter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Module state of one copter. */
struct swarm {
  struct swarm_params params;                         ///< the law's parameters (settings)
  struct swarm_target target;                         ///< the moving target (settings)
  bool use_wall_detector;                             ///< attraction from detected copters only (setting)
  struct swarm_echo echoes[WALL_DETECTOR_SONAR_NB];   ///< latest reading of each horizontal sonar
  struct swarm_peak_repulsion peak;                   ///< cache: the repulsion at the peak
  struct FloatVect2 velocity_ned;                     ///< last commanded velocity (north, east) [m/s]
  abi_event wall_detection_ev;                        ///< WALL_DETECTION binding
};

VEHICLE_LOCAL_DECLARE(struct swarm, swarm);

/** Module init: parameters from the SWARM_* defines, ABI binding. */
extern void swarm_init(void);
/** Module periodic (SWARM_PERIODIC_FREQ): compute and command the velocity. */
extern void swarm_periodic(void);

#ifdef __cplusplus
}
#endif

#endif /* SWARM_H */
