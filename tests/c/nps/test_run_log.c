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
 * @file test_run_log.c
 * Rows of poses.csv (nps_pose_log_row): the columns of the header in order, position and yaw as "%.4f", the
 * attitude quaternion as "%.9g" with qw >= 0 (a quaternion and its negative are one rotation) and no "-0"; a
 * heading's quaternion turns the body's x axis to the heading; the longest row fits the buffer.
 */
#include "test_helpers.h"
#include "nps_run_log.h"

#include <float.h>
#include <string.h>

static void a_row_has_the_headers_columns(void **state)
{
  (void)state;
  assert_string_equal(NPS_POSE_LOG_HEADER, "t,vehicle,x,y,z,yaw,qx,qy,qz,qw\n");
  char row[NPS_POSE_LOG_ROW_LEN + 1];
  const double pos[3] = { 1.25, -2.5, 0.6 }, q[4] = { 0.0, 0.0, 0.5, 0.8660254037844386 };
  const size_t len = nps_pose_log_row(row, 12.34, 7, pos, M_PI / 3, q);
  row[len] = '\0';
  assert_string_equal(row, "12.3400,7,1.2500,-2.5000,0.6000,1.0472,0,0,0.5,0.866025404\n");
}

static void the_quaternion_is_written_with_qw_not_negative_and_no_minus_zero(void **state)
{
  (void)state;
  char row[NPS_POSE_LOG_ROW_LEN + 1];
  const double pos[3] = { 0.0, 0.0, 0.0 };
  const double q[4] = { 0.0, -0.0, -0.6, -0.8 };   /* -q = (0, 0, 0.6, 0.8) */
  size_t len = nps_pose_log_row(row, 0.0, 1, pos, 0.0, q);
  row[len] = '\0';
  assert_string_equal(row, "0.0000,1,0.0000,0.0000,0.0000,0.0000,0,0,0.6,0.8\n");
  const double positive[4] = { 0.1, -0.0, 0.0, 0.9 };   /* kept as given, but for the sign of the zero */
  len = nps_pose_log_row(row, 0.0, 1, pos, 0.0, positive);
  row[len] = '\0';
  assert_string_equal(row, "0.0000,1,0.0000,0.0000,0.0000,0.0000,0.1,0,0,0.9\n");
}

static void a_headings_quaternion_turns_the_body_x_axis_to_the_heading(void **state)
{
  (void)state;
  uint32_t seed = 42;
  for (int k = 0; k < 1000; k++) {
    const double yaw = lcg_uniform(&seed, -M_PI, M_PI);
    double q[4];
    nps_pose_quat_of_yaw(yaw, q);
    assert_close(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-15);
    /* the body x axis rotated by q: first column of its matrix */
    const double x = 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2]), y = 2.0 * (q[0] * q[1] + q[3] * q[2]);
    assert_close(x, cos(yaw), 1e-15);
    assert_close(y, sin(yaw), 1e-15);
    assert_close(atan2(2.0 * (q[3] * q[2] + q[0] * q[1]), 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2])), yaw, 1e-14);
  }
}

static void the_longest_row_fits(void **state)
{
  (void)state;
  char row[NPS_POSE_LOG_ROW_LEN];
  const double pos[3] = { -1.2345678e300, -DBL_MAX, -1e-300 };
  const double q[4] = { -1.2345678901e-300, -1.2345678901e-300, -1.2345678901e-300, 1.0 };
  const size_t len = nps_pose_log_row(row, -DBL_MAX, 4294967295u, pos, -DBL_MAX, q);
  assert_true(len < sizeof(row));
  assert_int_equal(row[len - 1], '\n');
  assert_null(memchr(row, '\0', len));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(a_row_has_the_headers_columns),
    cmocka_unit_test(the_quaternion_is_written_with_qw_not_negative_and_no_minus_zero),
    cmocka_unit_test(a_headings_quaternion_turns_the_body_x_axis_to_the_heading),
    cmocka_unit_test(the_longest_row_fits),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
