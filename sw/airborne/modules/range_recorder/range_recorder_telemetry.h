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
 * @file modules/range_recorder/range_recorder_telemetry.h
 * The range recorder's telemetry: one pprzlink message per event (conf/telemetry/finken_messages.xml), on
 * Paparazzi's default downlink channel and device. Without a downlink in the build (no DOWNLINK: no telemetry
 * module, or our host) these do nothing. A seam: the glue's tests link their own versions of both.
 */

#ifndef RANGE_RECORDER_TELEMETRY_H
#define RANGE_RECORDER_TELEMETRY_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * FINKEN_RANGE_READING: stamp [us] (the copter's clock), sensor (enum range_recorder_sensor), peer (the ranged
 * aircraft's id, RANGE_RECORDER_NO_PEER for a sonar), measured [m] (NaN: no reading).
 */
extern void range_recorder_telemetry_reading(uint32_t stamp_us, uint8_t sensor, uint16_t peer, float measured_m);

/**
 * FINKEN_WALL_DECISION: stamp [us] of the reading judged, sonar (0 front, 1 right, 2 back, 3 left), the detector's
 * class and confidence, the reading [m], the single-reading check's class (class codes as WALL_DETECTION's).
 */
extern void range_recorder_telemetry_decision(uint32_t stamp_us, uint8_t sonar, uint8_t detector_class,
    float confidence, float measured_m, uint8_t baseline_class);

#ifdef __cplusplus
}
#endif

#endif /* RANGE_RECORDER_TELEMETRY_H */
