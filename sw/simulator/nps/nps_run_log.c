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
 * @file nps_run_log.c
 * Rows of poses.csv and detections.csv (see nps_run_log.h).
 */

#include "nps_run_log.h"

#include <math.h>

void nps_pose_quat_of_yaw(double yaw_rad, double q_xyzw[4])
{
  q_xyzw[0] = 0.0;
  q_xyzw[1] = 0.0;
  q_xyzw[2] = sin(0.5 * yaw_rad);
  q_xyzw[3] = cos(0.5 * yaw_rad);
}

size_t nps_pose_log_row(char *row, double t_s, unsigned ac_id, const double pos_m[3], double yaw_rad,
                        const double q_xyzw[4])
{
  char *p = row;
  p += nps_csv_fixed4(p, t_s);
  *p++ = ',';
  p += nps_csv_int(p, (long)ac_id);
  for (int k = 0; k < 4; k++) {
    *p++ = ',';
    p += nps_csv_fixed4(p, k < 3 ? pos_m[k] : yaw_rad);
  }
  /* the hemisphere qw >= 0; 0.0 - x and x + 0.0 turn a zero of either sign into +0: no "-0" */
  const bool flip = q_xyzw[3] < 0.0;
  for (int k = 0; k < 4; k++) {
    *p++ = ',';
    p += nps_csv_g9(p, flip ? 0.0 - q_xyzw[k] : q_xyzw[k] + 0.0);
  }
  *p++ = '\n';
  return (size_t)(p - row);
}

/** Write ",name" and then `after` at p (name cut to fit); returns the end. */
static char *put_name(char *p, const char *name, const char *after)
{
  const char *end = p + NPS_DETECTION_LOG_NAME_LEN - 4;
  *p++ = ',';
  while (*name != '\0' && p < end) {
    *p++ = *name++;
  }
  while (*after != '\0') {
    *p++ = *after++;
  }
  return p;
}

size_t nps_detection_log_row(char *row, const struct nps_detection *d)
{
  /* t,vehicle,sensor,peer (empty),true_range,measured,ctx_target_copter,detector_class,confidence,baseline_class */
  char *p = row;
  p += nps_csv_fixed4(p, d->t_s);
  *p++ = ',';
  p += nps_csv_int(p, (long)d->ac_id);
  p = put_name(p, d->sonar, ",,");
  p += nps_csv_fixed4(p, d->true_range_m);
  *p++ = ',';
  p += nps_csv_fixed4(p, d->measured_m);
  *p++ = ',';
  p += nps_csv_int(p, d->target_copter);
  p = put_name(p, d->detector_class, ",");
  p += nps_csv_fixed4(p, d->confidence);
  p = put_name(p, d->baseline_class, "\n");
  return (size_t)(p - row);
}
