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
 * @file modules/sonar/sonar_array.c
 * The FINken sonar ring: Paparazzi glue around the round robin (see sonar_array.h).
 */

#include "modules/sonar/sonar_array.h"
#include "modules/sonar/sonar_array_arch.h"
#include "modules/core/abi.h"
#include "mcu_periph/sys_time.h"

#include <stdio.h>

/* a check of the header's configuration (here, not in the header: C++ sources include it too) */
_Static_assert(0.0f <= SONAR_ARRAY_MIN_RANGE && SONAR_ARRAY_MIN_RANGE < SONAR_ARRAY_MAX_RANGE,
               "SONAR_ARRAY_MIN_RANGE must be at least 0 and below SONAR_ARRAY_MAX_RANGE");

#if PERIODIC_TELEMETRY
#include "modules/datalink/telemetry.h"

static void send_sonar_array(struct transport_tx *trans, struct link_device *dev)
{
  struct sonar_array *sa = VEHICLE_LOCAL(sonar_array);
  pprz_msg_send_SONAR_ARRAY(trans, dev, AC_ID, &sa->distance_m[SONAR_ARRAY_FRONT], &sa->distance_m[SONAR_ARRAY_RIGHT],
                            &sa->distance_m[SONAR_ARRAY_BACK], &sa->distance_m[SONAR_ARRAY_LEFT],
                            &sa->distance_m[SONAR_ARRAY_DOWN]);
}
#endif

VEHICLE_LOCAL_DEFINE(struct sonar_array, sonar_array);

const float sonar_array_heading_rad[SONAR_ARRAY_NB] = { 0.0f, M_PI / 2.0, M_PI, -M_PI / 2.0, 0.0f };
const float sonar_array_elevation_rad[SONAR_ARRAY_NB] = { 0.0f, 0.0f, 0.0f, 0.0f, -M_PI / 2.0 };
static const uint8_t sonar_array_sender_id[SONAR_ARRAY_NB] = {
  SONAR_ARRAY_FRONT_ID, SONAR_ARRAY_RIGHT_ID, SONAR_ARRAY_BACK_ID, SONAR_ARRAY_LEFT_ID, SONAR_ARRAY_DOWN_ID
};

float sonar_array_reported_distance(float raw_m)
{
  if (isnan(raw_m) || raw_m > SONAR_ARRAY_MAX_RANGE) {
    return SONAR_ARRAY_NO_ECHO_AS_MAX ? SONAR_ARRAY_MAX_RANGE : NAN;
  }
  return raw_m < SONAR_ARRAY_MIN_RANGE ? SONAR_ARRAY_MIN_RANGE : raw_m;
}

void sonar_array_init(void)
{
  struct sonar_array *sa = VEHICLE_LOCAL(sonar_array);
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    sa->distance_m[i] = NAN;
  }
  sa->running = sonar_array_schedule_init(&sa->schedule, SONAR_ARRAY_RATE, SONAR_ARRAY_READ_DELAY, get_sys_time_usec());
  const float round_trip_s = 2.0f * SONAR_ARRAY_MAX_RANGE / SONAR_ARRAY_SPEED_OF_SOUND;
  if (sa->running && sonar_array_schedule_window_s(&sa->schedule) < round_trip_s) {
    fprintf(stderr, "sonar_array: listening window %.1f ms (SONAR_ARRAY_READ_DELAY / (5 x SONAR_ARRAY_RATE)) is shorter "
            "than the echo round trip at SONAR_ARRAY_MAX_RANGE (%.1f ms): lower the rate or raise the delay\n",
            1e3f * sonar_array_schedule_window_s(&sa->schedule), 1e3f * round_trip_s);
    sa->running = false;
  }
  if (sa->running && !sonar_array_arch_init()) {
    sa->running = false;
  }
#if PERIODIC_TELEMETRY
  register_periodic_telemetry(DefaultPeriodic, PPRZ_MSG_ID_SONAR_ARRAY, send_sonar_array);
#endif
}

static void publish(struct sonar_array *sa, uint8_t sonar, float distance_m, uint32_t now_us)
{
  sa->distance_m[sonar] = distance_m;
  sa->stamp_us[sonar] = now_us;
  sa->count[sonar]++;
  if (sonar == SONAR_ARRAY_DOWN) {
    AbiSendMsgAGL(sonar_array_sender_id[sonar], now_us, distance_m);
  } else {
    AbiSendMsgOBSTACLE_DETECTION(sonar_array_sender_id[sonar], distance_m, sonar_array_elevation_rad[sonar],
                                 sonar_array_heading_rad[sonar]);
  }
}

void sonar_array_periodic(void)
{
  struct sonar_array *sa = VEHICLE_LOCAL(sonar_array);
  if (!sa->running) {
    return;
  }
  const uint32_t now_us = get_sys_time_usec();
  struct sonar_array_slot slot;
  if (!sonar_array_schedule_poll(&sa->schedule, now_us, &slot)) {
    return;
  }
  if (slot.read >= 0) {
    const float reported = sonar_array_reported_distance(sonar_array_arch_read(slot.read, slot.fired_at_us, now_us));
    if (!isnan(reported)) {
      publish(sa, slot.read, reported, now_us);
    }
  }
  sonar_array_arch_trigger(slot.fire, now_us);
}
