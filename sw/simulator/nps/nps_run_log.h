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
 * @file nps_run_log.h
 * Rows of a run's logs besides the range log, written by our host and by finken_world in Paparazzi's NPS:
 * poses.csv, where each copter is (at a fixed rate), and detections.csv, the wall detector's decisions with the
 * ground truth of the sonar reading each one judged (formats: tools/finken/run_logs.py).
 */

#ifndef NPS_RUN_LOG_H
#define NPS_RUN_LOG_H

#include "nps_csv.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NPS_POSE_LOG_HEADER "t,vehicle,x,y,z,yaw\n"
/** Room for any row of poses.csv. */
#define NPS_POSE_LOG_ROW_LEN (6 * (NPS_CSV_NUMBER_LEN + 1))

/** Format one row of poses.csv (newline included) in row (NPS_POSE_LOG_ROW_LEN): ENU position [m], yaw [rad]. */
extern size_t nps_pose_log_row(char *row, double t_s, unsigned ac_id, const double pos_m[3], double yaw_rad);

#define NPS_DETECTION_LOG_HEADER \
  "t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,detector_class,confidence,baseline_class\n"

/** Longest name written in a row (sonar and class names, cut to fit), its separators included. */
#define NPS_DETECTION_LOG_NAME_LEN 24
/** Room for any row. */
#define NPS_DETECTION_LOG_ROW_LEN (6 * (NPS_CSV_NUMBER_LEN + 1) + 4 * NPS_DETECTION_LOG_NAME_LEN)

/** One decision. */
struct nps_detection {
  double t_s;               ///< time of the decision [s]
  unsigned ac_id;           ///< the deciding aircraft
  const char *sonar;        ///< range-log name of the sonar judged ("sonar_front", ...)
  double true_range_m;      ///< ground truth of the reading [m]
  double measured_m;        ///< the distance the detector passed on [m]
  bool target_copter;       ///< the reading's first hit was a copter
  const char *detector_class, *baseline_class;   ///< "wall", "copter", "unknown", "none"
  double confidence;
};

/** Format d as one row (newline included) in row (NPS_DETECTION_LOG_ROW_LEN); returns its length. */
extern size_t nps_detection_log_row(char *row, const struct nps_detection *d);

#ifdef __cplusplus
}
#endif

#endif /* NPS_RUN_LOG_H */
