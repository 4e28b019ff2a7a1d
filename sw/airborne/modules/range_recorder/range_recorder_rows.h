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
 * @file modules/range_recorder/range_recorder_rows.h
 * The range recorder's pure part: the rows of its two CSV files, the names and codes of the sensors, the paths of
 * the files and the 64-bit clock of the rows. No clock, file or other OS call: the glue (range_recorder.c) passes
 * everything in.
 *
 * Readings file (one row per sonar reading and per ranging distance), the columns of a range log
 * (shared/spec/range-log.md) that a copter knows, without the ground truth:
 *
 *     t,vehicle,sensor,peer,measured
 *     12.350000,3,sonar_front,,1.27
 *     12.355120,3,ranging,2,1.4399999
 *
 * t [s] the copter's clock (microseconds, written exactly), vehicle its aircraft id, sensor one of sonar_front,
 * sonar_right, sonar_back, sonar_left, sonar_down, ranging; peer the ranged aircraft's id (empty for a sonar);
 * measured [m] the reading, empty when there is none (NaN), else the shortest decimal that reads back as the same
 * float.
 *
 * Decisions file (one row per WALL_DETECTION of the wall detector), the columns of detections.csv
 * (tools/finken/run_logs.py) that a copter knows:
 *
 *     t,vehicle,sensor,measured,detector_class,confidence,baseline_class
 *     12.350000,3,sonar_front,1.27,wall,0.98,wall
 *
 * classes: unknown, wall, copter, none (no echo), as wall_detector_class_name() names WALL_DETECTION's codes.
 */

#ifndef RANGE_RECORDER_ROWS_H
#define RANGE_RECORDER_ROWS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Sensor codes: the `sensor` field of FINKEN_RANGE_READING (the sonars in sonar_array's order). */
enum range_recorder_sensor {
  RANGE_RECORDER_SONAR_FRONT = 0,
  RANGE_RECORDER_SONAR_RIGHT = 1,
  RANGE_RECORDER_SONAR_BACK = 2,
  RANGE_RECORDER_SONAR_LEFT = 3,
  RANGE_RECORDER_SONAR_DOWN = 4,
  RANGE_RECORDER_RANGING = 5,
  RANGE_RECORDER_SENSOR_NB = 6
};

/** The `peer` of a sonar reading in FINKEN_RANGE_READING (no aircraft has this id). */
#define RANGE_RECORDER_NO_PEER 65535u

#define RANGE_RECORDER_READINGS_HEADER "t,vehicle,sensor,peer,measured\n"
#define RANGE_RECORDER_DECISIONS_HEADER "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n"
/** Room for any row of either file, its newline and a terminating NUL included. */
#define RANGE_RECORDER_ROW_LEN 160

/** One reading. */
struct range_recorder_reading {
  uint64_t t_us;         ///< the copter's clock [us]
  uint16_t vehicle;      ///< the copter's aircraft id
  uint8_t sensor;        ///< enum range_recorder_sensor
  uint16_t peer;         ///< ranging: the other copter's aircraft id (ignored for a sonar)
  float measured_m;      ///< the reading [m]; NaN: none
};

/** One decision of the wall detector (a WALL_DETECTION message). */
struct range_recorder_decision {
  uint64_t t_us;           ///< time of the sonar reading judged, the copter's clock [us]
  uint16_t vehicle;        ///< the copter's aircraft id
  uint8_t sonar;           ///< horizontal sonar, 0 front, 1 right, 2 back, 3 left
  float measured_m;        ///< the reading judged [m] (WALL_DETECTION's repulsion_distance)
  uint8_t detector_class;  ///< the detector's class (WALL_DETECTION's target_class)
  float confidence;        ///< the detector's confidence, 0.5 to 1
  uint8_t baseline_class;  ///< the single-reading check's class
};

/** The file name of a sensor ("sonar_front" ... "ranging"), NULL for a code that is none. */
extern const char *range_recorder_sensor_name(uint8_t sensor);

/** The code of a sensor's file name, -1 for a name that is none. */
extern int range_recorder_sensor_code(const char *name);

/** The file name of a WALL_DETECTION class code: "unknown", "wall", "copter", "none" (any other code: "unknown"). */
extern const char *range_recorder_class_name(uint8_t class_code);

/**
 * Format r as one row of the readings file, newline included, into row (len bytes, NUL-terminated).
 * Returns the row's length without the NUL; 0 (row left empty) for an unknown sensor or when len is too small
 * (RANGE_RECORDER_ROW_LEN is always enough).
 */
extern size_t range_recorder_reading_row(char *row, size_t len, const struct range_recorder_reading *r);

/**
 * Format d as one row of the decisions file, as range_recorder_reading_row; 0 for a sonar that is not a horizontal
 * one (0..3) or when len is too small.
 */
extern size_t range_recorder_decision_row(char *row, size_t len, const struct range_recorder_decision *d);

/**
 * The path of one of the recorder's files into path (len bytes): "<dir>/<name>_<ac_id>.csv" when dir is neither
 * NULL nor empty (NPS: the run's output folder), else `pattern` with each "{ac_id}" replaced by ac_id.
 * Returns the path's length; 0 for no file (no dir and an empty or NULL pattern); -1 when it does not fit in len.
 */
extern int range_recorder_file_path(char *path, size_t len, const char *dir, const char *name, const char *pattern,
                                    unsigned ac_id);

/**
 * A 64-bit microsecond clock from the 32-bit stamps of ABI and get_sys_time_usec() (they wrap after 71.6 min):
 * each stamp is taken as the one nearest the latest stamp seen (within +-35.8 min).
 */
struct range_recorder_clock {
  uint64_t latest_us;   ///< the latest time given so far
  bool started;         ///< a stamp was given
};

/** The stamp's time on the 64-bit clock; moves the clock on when it is the latest so far. */
extern uint64_t range_recorder_clock_us(struct range_recorder_clock *clock, uint32_t stamp_us);

#ifdef __cplusplus
}
#endif

#endif /* RANGE_RECORDER_ROWS_H */
