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
 * @file modules/range_recorder/range_recorder_telemetry.c
 * The range recorder's telemetry messages on Paparazzi's default downlink (see range_recorder_telemetry.h).
 */

#include "modules/range_recorder/range_recorder_telemetry.h"

#if defined(DOWNLINK) && DOWNLINK
#include "modules/datalink/downlink.h"   /* DefaultChannel, DefaultDevice, AC_ID, the generated pprz_msg_send_ */

void range_recorder_telemetry_reading(uint32_t stamp_us, uint8_t sensor, uint16_t peer, float measured_m)
{
  pprz_msg_send_FINKEN_RANGE_READING(&(DefaultChannel).trans_tx, &(DefaultDevice).device, AC_ID, &stamp_us, &sensor,
                                     &peer, &measured_m);
}

void range_recorder_telemetry_decision(uint32_t stamp_us, uint8_t sonar, uint8_t detector_class, float confidence,
                                       float measured_m, uint8_t baseline_class)
{
  pprz_msg_send_FINKEN_WALL_DECISION(&(DefaultChannel).trans_tx, &(DefaultDevice).device, AC_ID, &stamp_us, &sonar,
                                     &detector_class, &confidence, &measured_m, &baseline_class);
}

#else   /* no downlink in this build */

void range_recorder_telemetry_reading(uint32_t stamp_us, uint8_t sensor, uint16_t peer, float measured_m)
{
  (void)stamp_us, (void)sensor, (void)peer, (void)measured_m;
}

void range_recorder_telemetry_decision(uint32_t stamp_us, uint8_t sonar, uint8_t detector_class, float confidence,
                                       float measured_m, uint8_t baseline_class)
{
  (void)stamp_us, (void)sonar, (void)detector_class, (void)confidence, (void)measured_m, (void)baseline_class;
}

#endif
