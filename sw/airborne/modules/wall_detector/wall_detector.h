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
 * @file modules/wall_detector/wall_detector.h
 * Paparazzi module: tells walls from copters in the horizontal sonar readings.
 *
 * Inputs (ABI): OBSTACLE_DETECTION from the horizontal sonars (sonar picked by its heading) and
 * RANGING_DISTANCE from the ranging unit; the pose from the state interface.
 * Output (ABI): one WALL_DETECTION per horizontal reading, with sender WALL_DETECTOR_SENDER_ID.
 * The logic is wall_detector_filter.c; this file only binds it.
 */

#ifndef WALL_DETECTOR_H
#define WALL_DETECTOR_H

#include "modules/core/abi.h"
#include "modules/multi_vehicle/vehicle_local.h"
#include "modules/wall_detector/wall_detector_filter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** ABI sender id of WALL_DETECTION. */
#ifndef WALL_DETECTOR_SENDER_ID
#define WALL_DETECTOR_SENDER_ID 1
#endif

/** Module state of one copter. */
struct wall_detector {
  struct wall_detector_filter filter;  ///< the detector (its params are the settings)
  abi_event obstacle_ev;               ///< OBSTACLE_DETECTION binding
  abi_event ranging_ev;                ///< RANGING_DISTANCE binding
};

VEHICLE_LOCAL_DECLARE(struct wall_detector, wall_detector);

/** Module init: parameters from the WALL_DETECTOR_* defines, ABI bindings. */
extern void wall_detector_init(void);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_H */
