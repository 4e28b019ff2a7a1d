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
 * @file modules/swarm/swarm.c
 * Paparazzi glue of the swarm: WALL_DETECTION in, the law, autopilot_guided_move_ned out. Defaults of
 * every define are listed (with their sources) in conf/modules/swarm.xml.
 */

#include "modules/swarm/swarm.h"

#include "firmwares/rotorcraft/autopilot_guided.h"
#include "mcu_periph/sys_time.h"
#include "state.h"

/* The FINken V-REP swarm's parameters (finken_util_with_Virtual_Ranging_Wall_Check.lua, prepareConfig). */
#ifndef SWARM_A
#define SWARM_A 1.0f
#endif
#ifndef SWARM_B
#define SWARM_B 4.0f
#endif
#ifndef SWARM_C
#define SWARM_C 1.5f
#endif
#ifndef SWARM_COHESION_WEIGHT
#define SWARM_COHESION_WEIGHT 0.8f
#endif
#ifndef SWARM_TARGET_WEIGHT
#define SWARM_TARGET_WEIGHT 0.2f
#endif
/* Ours: the velocity loop and the target. */
#ifndef SWARM_GAIN
#define SWARM_GAIN 1.0f
#endif
#ifndef SWARM_MAX_SPEED
#define SWARM_MAX_SPEED 0.5f
#endif
#ifndef SWARM_ECHO_TIMEOUT
#define SWARM_ECHO_TIMEOUT 0.5f
#endif
#ifndef SWARM_TARGET_EAST
#define SWARM_TARGET_EAST 1.5f
#endif
#ifndef SWARM_TARGET_NORTH
#define SWARM_TARGET_NORTH 2.0f
#endif
#ifndef SWARM_TARGET_RADIUS
#define SWARM_TARGET_RADIUS 1.0f
#endif
#ifndef SWARM_TARGET_PERIOD
#define SWARM_TARGET_PERIOD 60.0f
#endif
#ifndef SWARM_USE_WALL_DETECTOR
#define SWARM_USE_WALL_DETECTOR TRUE
#endif
#ifndef SWARM_WALL_DETECTION_SENDER_ID
#define SWARM_WALL_DETECTION_SENDER_ID ABI_BROADCAST
#endif

/* A define out of range stops the build here rather than flying a silently wrong swarm. */
_Static_assert(SWARM_A >= 0.f && SWARM_B >= 0.f && SWARM_C > 0.f, "need SWARM_A >= 0, SWARM_B >= 0, SWARM_C > 0 [m^2]");
_Static_assert(SWARM_COHESION_WEIGHT >= 0.f && SWARM_TARGET_WEIGHT >= 0.f, "SWARM_*_WEIGHT must be >= 0");
_Static_assert(SWARM_GAIN > 0.f && SWARM_MAX_SPEED > 0.f && SWARM_ECHO_TIMEOUT > 0.f,
               "SWARM_GAIN [1/s], SWARM_MAX_SPEED [m/s] and SWARM_ECHO_TIMEOUT [s] must be > 0");
_Static_assert(SWARM_TARGET_RADIUS >= 0.f && SWARM_TARGET_PERIOD >= 0.f,
               "SWARM_TARGET_RADIUS [m] and SWARM_TARGET_PERIOD [s] must be >= 0");

VEHICLE_LOCAL_DEFINE(struct swarm, swarm);

static void swarm_wall_detection_cb(uint8_t sender_id, uint32_t stamp, uint8_t sonar, float heading,
                                    uint8_t target_class, float confidence, float attraction_distance,
                                    float repulsion_distance, uint8_t baseline_class)
{
  (void)sender_id;
  (void)confidence;
  (void)baseline_class;
  if (sonar >= WALL_DETECTOR_SONAR_NB) {
    return;
  }
  VEHICLE_LOCAL(swarm)->echoes[sonar] = (struct swarm_echo) {
    .valid = true,
    .stamp_us = stamp,
    .heading_rad = heading,
    .target_class = (enum wall_detector_class)target_class,
    .attraction_m = attraction_distance,
    .repulsion_m = repulsion_distance,
  };
}

void swarm_init(void)
{
  struct swarm *sw = VEHICLE_LOCAL(swarm);
  *sw = (struct swarm) {
    .params = {
      .a = SWARM_A,
      .b = SWARM_B,
      .c_m2 = SWARM_C,
      .cohesion_weight = SWARM_COHESION_WEIGHT,
      .target_weight = SWARM_TARGET_WEIGHT,
      .gain_per_s = SWARM_GAIN,
      .max_speed_mps = SWARM_MAX_SPEED,
      .echo_timeout_s = SWARM_ECHO_TIMEOUT,
    },
    .target = {
      .centre_east_m = SWARM_TARGET_EAST,
      .centre_north_m = SWARM_TARGET_NORTH,
      .radius_m = SWARM_TARGET_RADIUS,
      .period_s = SWARM_TARGET_PERIOD,
    },
    .use_wall_detector = SWARM_USE_WALL_DETECTOR,
  };
  AbiBindMsgWALL_DETECTION(SWARM_WALL_DETECTION_SENDER_ID, &sw->wall_detection_ev, swarm_wall_detection_cb);
}

void swarm_periodic(void)
{
  struct swarm *sw = VEHICLE_LOCAL(swarm);
  const uint32_t now_us = get_sys_time_usec();
  const float yaw_rad = stateGetNedToBodyEulers_f()->psi;
  const struct NedCoor_f *pos = stateGetPositionNed_f();
  const struct FloatVect2 pos_ned = { pos->x, pos->y };
  struct FloatVect2 cohesion_ned, target_ned;
  swarm_cohesion_ned(&sw->params, sw->echoes, WALL_DETECTOR_SONAR_NB, yaw_rad, now_us, sw->use_wall_detector,
                     &sw->peak, &cohesion_ned);
  swarm_target_ned(&sw->target, (float)(now_us * 1e-6), &target_ned);
  swarm_velocity_ned(&sw->params, &cohesion_ned, &pos_ned, &target_ned, &sw->velocity_ned);
  autopilot_guided_move_ned(sw->velocity_ned.x, sw->velocity_ned.y, 0.f, yaw_rad);
}
