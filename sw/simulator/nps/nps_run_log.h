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
 * poses.csv, where each copter is and how it is turned (at a fixed rate), and detections.csv, the wall detector's
 * decisions with the ground truth of the sonar reading each one judged (formats: tools/finken/run_logs.py).
 *
 * A pose's attitude is the unit quaternion (qx, qy, qz, qw), scalar last, of the rotation that turns the copter's
 * body frame (x forward, y left, z up) into the arena frame ENU (x east, y north, z up): a vector b in body
 * coordinates is q b q* in arena coordinates (Hamilton product). A copter turned by yaw about z alone has
 * q = (0, 0, sin(yaw/2), cos(yaw/2)); in general yaw = atan2(2 (qw qz + qx qy), 1 - 2 (qy^2 + qz^2)).
 */

#ifndef NPS_RUN_LOG_H
#define NPS_RUN_LOG_H

#include "nps_csv.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NPS_POSE_LOG_HEADER "t,vehicle,x,y,z,yaw,qx,qy,qz,qw\n"
/** Room for any row of poses.csv. */
#define NPS_POSE_LOG_ROW_LEN (10 * (NPS_CSV_NUMBER_LEN + 1))

/** The attitude quaternion (qx, qy, qz, qw) of a copter turned by yaw_rad about the arena's z alone. */
extern void nps_pose_quat_of_yaw(double yaw_rad, double q_xyzw[4]);

/**
 * Format one row of poses.csv (newline included) in row (NPS_POSE_LOG_ROW_LEN): ENU position [m], yaw [rad] and
 * the attitude quaternion q_xyzw (see above; q and -q are the same rotation: written with qw >= 0); returns its
 * length. Position and yaw as "%.4f", the quaternion as "%.9g" (a zero as "0", never "-0").
 */
extern size_t nps_pose_log_row(char *row, double t_s, unsigned ac_id, const double pos_m[3], double yaw_rad,
                               const double q_xyzw[4]);

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
