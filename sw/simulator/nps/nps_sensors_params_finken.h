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
 * @file nps_sensors_params_finken.h
 * Paparazzi NPS sensor parameters of the FINken (Paparazzi builds only: it includes Paparazzi's
 * nps_sensors_params_default.h). The airframe selects it for its nps target:
 *   <define name="NPS_SENSORS_PARAMS" value="nps_sensors_params_finken.h" type="string"/>
 * and sets the IMU errors in its SIMULATOR section (prefix NPS_), as tools/imu_calibrate.py writes them:
 * GYRO_NOISE_STD_DEV_P/Q/R, GYRO_BIAS_INITIAL_P/Q/R, GYRO_BIAS_RANDOM_WALK_STD_DEV_P/Q/R, ACCEL_NOISE_STD_DEV_X/Y/Z,
 * ACCEL_BIAS_X/Y/Z (and GYRO_DT, ACCEL_DT, which Paparazzi's defaults leave to the airframe). Paparazzi's parameter
 * headers define these without #ifndef, after generated/airframe.h: the airframe's values are set aside around them
 * (GCC's push_macro) and put back, everything else is Paparazzi's default. A missing one stops the build.
 */

#ifndef NPS_SENSORS_PARAMS_FINKEN_H
#define NPS_SENSORS_PARAMS_FINKEN_H

#include "generated/airframe.h"

#if !defined(NPS_GYRO_NOISE_STD_DEV_P) || !defined(NPS_GYRO_NOISE_STD_DEV_Q) || !defined(NPS_GYRO_NOISE_STD_DEV_R) \
  || !defined(NPS_GYRO_BIAS_INITIAL_P) || !defined(NPS_GYRO_BIAS_INITIAL_Q) || !defined(NPS_GYRO_BIAS_INITIAL_R) \
  || !defined(NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_P) || !defined(NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_Q) \
  || !defined(NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_R) || !defined(NPS_ACCEL_NOISE_STD_DEV_X) \
  || !defined(NPS_ACCEL_NOISE_STD_DEV_Y) || !defined(NPS_ACCEL_NOISE_STD_DEV_Z) || !defined(NPS_ACCEL_BIAS_X) \
  || !defined(NPS_ACCEL_BIAS_Y) || !defined(NPS_ACCEL_BIAS_Z)
#error "the airframe's SIMULATOR section (prefix NPS_) lacks an IMU error define: tools/imu_calibrate.py writes them all (docs/imu-and-floor.md)"
#endif

#pragma push_macro("NPS_GYRO_NOISE_STD_DEV_P")
#pragma push_macro("NPS_GYRO_NOISE_STD_DEV_Q")
#pragma push_macro("NPS_GYRO_NOISE_STD_DEV_R")
#pragma push_macro("NPS_GYRO_BIAS_INITIAL_P")
#pragma push_macro("NPS_GYRO_BIAS_INITIAL_Q")
#pragma push_macro("NPS_GYRO_BIAS_INITIAL_R")
#pragma push_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_P")
#pragma push_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_Q")
#pragma push_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_R")
#pragma push_macro("NPS_ACCEL_NOISE_STD_DEV_X")
#pragma push_macro("NPS_ACCEL_NOISE_STD_DEV_Y")
#pragma push_macro("NPS_ACCEL_NOISE_STD_DEV_Z")
#pragma push_macro("NPS_ACCEL_BIAS_X")
#pragma push_macro("NPS_ACCEL_BIAS_Y")
#pragma push_macro("NPS_ACCEL_BIAS_Z")
#undef NPS_GYRO_NOISE_STD_DEV_P
#undef NPS_GYRO_NOISE_STD_DEV_Q
#undef NPS_GYRO_NOISE_STD_DEV_R
#undef NPS_GYRO_BIAS_INITIAL_P
#undef NPS_GYRO_BIAS_INITIAL_Q
#undef NPS_GYRO_BIAS_INITIAL_R
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_P
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_Q
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_R
#undef NPS_ACCEL_NOISE_STD_DEV_X
#undef NPS_ACCEL_NOISE_STD_DEV_Y
#undef NPS_ACCEL_NOISE_STD_DEV_Z
#undef NPS_ACCEL_BIAS_X
#undef NPS_ACCEL_BIAS_Y
#undef NPS_ACCEL_BIAS_Z

#include "nps_sensors_params_default.h"

#undef NPS_GYRO_NOISE_STD_DEV_P
#undef NPS_GYRO_NOISE_STD_DEV_Q
#undef NPS_GYRO_NOISE_STD_DEV_R
#undef NPS_GYRO_BIAS_INITIAL_P
#undef NPS_GYRO_BIAS_INITIAL_Q
#undef NPS_GYRO_BIAS_INITIAL_R
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_P
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_Q
#undef NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_R
#undef NPS_ACCEL_NOISE_STD_DEV_X
#undef NPS_ACCEL_NOISE_STD_DEV_Y
#undef NPS_ACCEL_NOISE_STD_DEV_Z
#undef NPS_ACCEL_BIAS_X
#undef NPS_ACCEL_BIAS_Y
#undef NPS_ACCEL_BIAS_Z
#pragma pop_macro("NPS_GYRO_NOISE_STD_DEV_P")
#pragma pop_macro("NPS_GYRO_NOISE_STD_DEV_Q")
#pragma pop_macro("NPS_GYRO_NOISE_STD_DEV_R")
#pragma pop_macro("NPS_GYRO_BIAS_INITIAL_P")
#pragma pop_macro("NPS_GYRO_BIAS_INITIAL_Q")
#pragma pop_macro("NPS_GYRO_BIAS_INITIAL_R")
#pragma pop_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_P")
#pragma pop_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_Q")
#pragma pop_macro("NPS_GYRO_BIAS_RANDOM_WALK_STD_DEV_R")
#pragma pop_macro("NPS_ACCEL_NOISE_STD_DEV_X")
#pragma pop_macro("NPS_ACCEL_NOISE_STD_DEV_Y")
#pragma pop_macro("NPS_ACCEL_NOISE_STD_DEV_Z")
#pragma pop_macro("NPS_ACCEL_BIAS_X")
#pragma pop_macro("NPS_ACCEL_BIAS_Y")
#pragma pop_macro("NPS_ACCEL_BIAS_Z")

#endif /* NPS_SENSORS_PARAMS_FINKEN_H */
