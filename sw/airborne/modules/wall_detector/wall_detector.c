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
 * @file modules/wall_detector/wall_detector.c
 * Paparazzi glue of the wall detector: ABI in, the filter, ABI out. Defaults of every define are
 * listed (with their sources) in conf/modules/wall_detector.xml.
 */

#include "modules/wall_detector/wall_detector.h"

#include "mcu_periph/sys_time.h"
#include "state.h"

/*
 * Defaults. The error model must match the airframe's sensor model; these match the project's defaults:
 * conf/sensor_models/finken_default.xml (sonar), conf/sensor_models/finken_ranging_gmm_k100.xml (ranging) and
 * conf/arena/swarmlab.xml (body and sonar geometry). The filter's constants are ours (docs/wall-detector.md).
 */
/** Rayleigh sigma of the sonar's short readings [m] (finken_default.xml rayleigh_short sigma) */
#ifndef WALL_DETECTOR_SONAR_SIGMA
#define WALL_DETECTOR_SONAR_SIGMA 0.05f
#endif
/** sqrt((4 - pi) / 2): the Rayleigh standard deviation per unit sigma (report section 3.2) */
#define WALL_DETECTOR_RAYLEIGH_SD_PER_SIGMA 0.6551363775620336f
/** Offset of the short-reading error [m] (the report's and the sensor model's default: the Rayleigh sd) */
#ifndef WALL_DETECTOR_SONAR_OFFSET
#define WALL_DETECTOR_SONAR_OFFSET (WALL_DETECTOR_RAYLEIGH_SD_PER_SIGMA * WALL_DETECTOR_SONAR_SIGMA)
#endif
/** Sonar reading limits [m] (report section 3.2; SONAR_ARRAY_MIN_RANGE, SONAR_ARRAY_MAX_RANGE) */
#ifndef WALL_DETECTOR_SONAR_MIN
#define WALL_DETECTOR_SONAR_MIN 0.2f
#endif
#ifndef WALL_DETECTOR_SONAR_MAX
#define WALL_DETECTOR_SONAR_MAX 3.0f
#endif
/** Ranging error sd [m]: the default mixture's conditional sd at mid range (0.09 m at 0.25 m, 0.17 m at 2.5 m) */
#ifndef WALL_DETECTOR_RANGING_SIGMA
#define WALL_DETECTOR_RANGING_SIGMA 0.12f
#endif
/** Ranging maximum [m] (report section 4.1; VIRTUAL_RANGING_MAX_RANGE) */
#ifndef WALL_DETECTOR_RANGING_MAX
#define WALL_DETECTOR_RANGING_MAX 2.5f
#endif
/** Ranged distance minus the sonar range of that copter [m]: body radius 0.2 + sonar offset 0 + ranging bias 0.04 */
#ifndef WALL_DETECTOR_COPTER_OFFSET
#define WALL_DETECTOR_COPTER_OFFSET 0.24f
#endif
/** Radius of a copter's body [m] (conf/arena/swarmlab.xml: 0.4 m across with the propeller guard) */
#ifndef WALL_DETECTOR_COPTER_RADIUS
#define WALL_DETECTOR_COPTER_RADIUS 0.2f
#endif
/** sd of a wall's reading about the range its previous reading predicts [m]: two readings' Rayleigh errors,
 * sqrt(2) x 0.0328 = 0.046, and 0.02 for the curtain's sway and the pose's error */
#ifndef WALL_DETECTOR_TRACK_SIGMA
#define WALL_DETECTOR_TRACK_SIGMA 0.05f
#endif
/** Probability that a copter echo reads as cross-talk, half the ranged distance (ours; the report's 68 % is
 * for copters facing each other, most copter echoes are not from a facing sonar) */
#ifndef WALL_DETECTOR_CROSSTALK_PROB
#define WALL_DETECTOR_CROSSTALK_PROB 0.1f
#endif
/** Probability that a copter echo reads as anything (ours) */
#ifndef WALL_DETECTOR_OUTLIER_PROB
#define WALL_DETECTOR_OUTLIER_PROB 0.1f
#endif
/** Time constant of the evidence decay [s] */
#ifndef WALL_DETECTOR_EVIDENCE_TAU
#define WALL_DETECTOR_EVIDENCE_TAU 10.0f
#endif
/** Translation over which evidence fades by 1/e [m] */
#ifndef WALL_DETECTOR_MOVE_SCALE
#define WALL_DETECTOR_MOVE_SCALE 3.0f
#endif
/** Yaw change over which evidence fades by 1/e [rad] */
#ifndef WALL_DETECTOR_TURN_SCALE
#define WALL_DETECTOR_TURN_SCALE 0.5f
#endif
/** A reading this far from the sonar's previous one starts new evidence [m] */
#ifndef WALL_DETECTOR_JUMP
#define WALL_DETECTOR_JUMP 0.25f
#endif
/** Bound of each peer's evidence [log-likelihood ratio]: about 7 readings at the best fit (llr about 1.5); a few
 * readings unlike the peer (llr down to log(OUTLIER_PROB) = -2.3 each) overturn a coincidence's evidence */
#ifndef WALL_DETECTOR_EVIDENCE_MAX
#define WALL_DETECTOR_EVIDENCE_MAX 10.0f
#endif
/** Wall at posterior log-odds <= -WALL_THRESHOLD, copter at >= COPTER_THRESHOLD: the likelier class's posterior
 * at least e / (1 + e) = 0.73 either way */
#ifndef WALL_DETECTOR_WALL_THRESHOLD
#define WALL_DETECTOR_WALL_THRESHOLD 1.0f
#endif
#ifndef WALL_DETECTOR_COPTER_THRESHOLD
#define WALL_DETECTOR_COPTER_THRESHOLD 1.0f
#endif
/** Ranging older than this is ignored [s] (as VIRTUAL_RANGING_STALE_TIME) */
#ifndef WALL_DETECTOR_PEER_TIMEOUT
#define WALL_DETECTOR_PEER_TIMEOUT 0.5f
#endif
/** The original check's tolerance [m] (finken_util_with_Virtual_Ranging_Wall_Check.lua, isFinken) */
#ifndef WALL_DETECTOR_BASELINE_EPS
#define WALL_DETECTOR_BASELINE_EPS 0.286319104f
#endif
/** Largest |elevation| of a horizontal sonar [rad] (others, e.g. a downward one, are ignored) */
#ifndef WALL_DETECTOR_MAX_ELEVATION
#define WALL_DETECTOR_MAX_ELEVATION 0.35f
#endif
/** Remember the walls for the whole flight in a map learned by all four sonars (wall_detector_map.h); FALSE: each
 * sonar remembers the wall it judged over the last 2 s (the law before the map, for comparison) */
#ifndef WALL_DETECTOR_MAP
#define WALL_DETECTOR_MAP TRUE
#endif
/** Diffusion of the position estimate's error per axis [m^2/s]: 2 sd^2 tau of a velocity error of sd 0.02 m/s
 * correlated over 10 s (a velocity-aided INS, as the host's --ins-drift 0.02: sw/simulator/nps/nps_ins_drift.h) */
#ifndef WALL_DETECTOR_MAP_DRIFT
#define WALL_DETECTOR_MAP_DRIFT 0.008f
#endif
/** Prior sd of a new wall's angle from square to the beam that first saw it [rad] (1 rad: up to about 60 deg) */
#ifndef WALL_DETECTOR_MAP_ANGLE_SD
#define WALL_DETECTOR_MAP_ANGLE_SD 1.0f
#endif
/** How far in front of its line a curtain wall's echo may read when the curtain bulges toward a copter near it [m]
 * (our arena model's SwarmLab curtains: up to 0.37 m at flight height, 0.27 m in 99 % of the wall snapshots of an
 * 8-copter run; and the sonar's short readings, up to 0.15 m in 99.9 %) */
#ifndef WALL_DETECTOR_CURTAIN_BULGE
#define WALL_DETECTOR_CURTAIN_BULGE 0.5f
#endif
/** Probability that a wall echo comes from a bulge (ours: readings of 8-copter runs beyond 0.05 m in front of the
 * rigid wall, a quarter at 1.25 m from it and most within 0.75 m) */
#ifndef WALL_DETECTOR_CURTAIN_BULGE_PROB
#define WALL_DETECTOR_CURTAIN_BULGE_PROB 0.3f
#endif
/** Sender ids bound for the inputs (ABI_BROADCAST: any) */
#ifndef WALL_DETECTOR_OBSTACLE_SENDER_ID
#define WALL_DETECTOR_OBSTACLE_SENDER_ID ABI_BROADCAST
#endif
#ifndef WALL_DETECTOR_RANGING_SENDER_ID
#define WALL_DETECTOR_RANGING_SENDER_ID ABI_BROADCAST
#endif

/* A define out of range stops the build here rather than flying a silently wrong detector. */
_Static_assert(WALL_DETECTOR_SONAR_SIGMA > 0.f, "WALL_DETECTOR_SONAR_SIGMA must be > 0 [m]");
_Static_assert(WALL_DETECTOR_RANGING_SIGMA > 0.f, "WALL_DETECTOR_RANGING_SIGMA must be > 0 [m]");
_Static_assert(WALL_DETECTOR_SONAR_MIN >= 0.f && WALL_DETECTOR_SONAR_MIN < WALL_DETECTOR_SONAR_MAX,
               "need 0 <= WALL_DETECTOR_SONAR_MIN < WALL_DETECTOR_SONAR_MAX [m]");
_Static_assert(WALL_DETECTOR_RANGING_MAX > 0.f, "WALL_DETECTOR_RANGING_MAX must be > 0 [m]");
_Static_assert(WALL_DETECTOR_COPTER_RADIUS > 0.f && WALL_DETECTOR_TRACK_SIGMA > 0.f,
               "WALL_DETECTOR_COPTER_RADIUS [m] and WALL_DETECTOR_TRACK_SIGMA [m] must be > 0");
_Static_assert(WALL_DETECTOR_TRACK_READINGS >= 1 && WALL_DETECTOR_TRACK_READINGS <= 65535,
               "WALL_DETECTOR_TRACK_READINGS must be 1..65535 (readings)");
_Static_assert(WALL_DETECTOR_OUTLIER_PROB > 0.f && WALL_DETECTOR_CROSSTALK_PROB >= 0.f &&
               WALL_DETECTOR_OUTLIER_PROB + WALL_DETECTOR_CROSSTALK_PROB < 1.f,
               "need WALL_DETECTOR_OUTLIER_PROB > 0, WALL_DETECTOR_CROSSTALK_PROB >= 0, their sum < 1");
_Static_assert(WALL_DETECTOR_EVIDENCE_TAU > 0.f && WALL_DETECTOR_MOVE_SCALE > 0.f && WALL_DETECTOR_TURN_SCALE > 0.f,
               "WALL_DETECTOR_EVIDENCE_TAU [s], _MOVE_SCALE [m] and _TURN_SCALE [rad] must be > 0");
_Static_assert(WALL_DETECTOR_JUMP > 0.f && WALL_DETECTOR_EVIDENCE_MAX > 0.f && WALL_DETECTOR_EVIDENCE_MAX <= 80.f,
               "need WALL_DETECTOR_JUMP > 0 [m] and 0 < WALL_DETECTOR_EVIDENCE_MAX <= 80 (the decision weighs with "
               "expf(evidence), finite below 88)");
_Static_assert(WALL_DETECTOR_WALL_THRESHOLD >= 0.f && WALL_DETECTOR_COPTER_THRESHOLD > 0.f,
               "need WALL_DETECTOR_WALL_THRESHOLD >= 0 and WALL_DETECTOR_COPTER_THRESHOLD > 0");
_Static_assert(WALL_DETECTOR_MAP_DRIFT >= 0.f && WALL_DETECTOR_MAP_ANGLE_SD > 0.f,
               "need WALL_DETECTOR_MAP_DRIFT >= 0 [m^2/s] and WALL_DETECTOR_MAP_ANGLE_SD > 0 [rad]");
_Static_assert(WALL_DETECTOR_CURTAIN_BULGE > 0.f && WALL_DETECTOR_CURTAIN_BULGE_PROB >= 0.f &&
               WALL_DETECTOR_CURTAIN_BULGE_PROB <= 1.f,
               "need WALL_DETECTOR_CURTAIN_BULGE > 0 [m] and 0 <= WALL_DETECTOR_CURTAIN_BULGE_PROB <= 1");
_Static_assert(WALL_DETECTOR_PEER_TIMEOUT > 0.f && WALL_DETECTOR_BASELINE_EPS > 0.f,
               "WALL_DETECTOR_PEER_TIMEOUT [s] and WALL_DETECTOR_BASELINE_EPS [m] must be > 0");

VEHICLE_LOCAL_DEFINE(struct wall_detector, wall_detector);

static void wall_detector_obstacle_cb(uint8_t sender_id, float distance, float elevation, float heading)
{
  (void)sender_id;
  if (!(fabsf(elevation) <= WALL_DETECTOR_MAX_ELEVATION)) {
    return;  // not a horizontal sonar
  }
  const struct EnuCoor_f *pos = stateGetPositionEnu_f();
  const struct wall_detector_pose pose = { pos->x, pos->y, stateGetNedToBodyEulers_f()->psi };
  const uint32_t now_us = get_sys_time_usec();
  const int sonar = wall_detector_sonar_index(heading);
  struct wall_detector_decision d;
  if (wall_detector_filter_sonar(&VEHICLE_LOCAL(wall_detector)->filter, sonar, distance, &pose, now_us, &d) == 0) {
    AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, now_us, (uint8_t)sonar, heading, (uint8_t)d.target_class,
                             d.confidence, d.attraction_m, d.repulsion_m, (uint8_t)d.baseline_class);
  }
}

static void wall_detector_ranging_cb(uint8_t sender_id, uint32_t stamp, uint16_t peer_id, float distance)
{
  (void)sender_id;
  wall_detector_filter_ranging(&VEHICLE_LOCAL(wall_detector)->filter, peer_id, distance, stamp);
}

void wall_detector_init(void)
{
  const struct wall_detector_params params = {
    .model = {
      .sonar_sigma_m = WALL_DETECTOR_SONAR_SIGMA,
      .sonar_offset_m = WALL_DETECTOR_SONAR_OFFSET,
      .ranging_sigma_m = WALL_DETECTOR_RANGING_SIGMA,
      .copter_offset_m = WALL_DETECTOR_COPTER_OFFSET,
      .crosstalk_prob = WALL_DETECTOR_CROSSTALK_PROB,
      .outlier_prob = WALL_DETECTOR_OUTLIER_PROB,
      .sonar_min_m = WALL_DETECTOR_SONAR_MIN,
      .sonar_max_m = WALL_DETECTOR_SONAR_MAX,
      .ranging_max_m = WALL_DETECTOR_RANGING_MAX,
      .copter_radius_m = WALL_DETECTOR_COPTER_RADIUS,
      .track_sigma_m = WALL_DETECTOR_TRACK_SIGMA,
    },
    .evidence_tau_s = WALL_DETECTOR_EVIDENCE_TAU,
    .move_scale_m = WALL_DETECTOR_MOVE_SCALE,
    .turn_scale_rad = WALL_DETECTOR_TURN_SCALE,
    .jump_m = WALL_DETECTOR_JUMP,
    .evidence_max = WALL_DETECTOR_EVIDENCE_MAX,
    .wall_threshold = WALL_DETECTOR_WALL_THRESHOLD,
    .copter_threshold = WALL_DETECTOR_COPTER_THRESHOLD,
    .peer_timeout_s = WALL_DETECTOR_PEER_TIMEOUT,
    .baseline_eps_m = WALL_DETECTOR_BASELINE_EPS,
    .use_map = WALL_DETECTOR_MAP,
    .map = {
      .drift_m2_per_s = WALL_DETECTOR_MAP_DRIFT, .angle_sd_rad = WALL_DETECTOR_MAP_ANGLE_SD,
      .bulge_m = WALL_DETECTOR_CURTAIN_BULGE, .bulge_prob = WALL_DETECTOR_CURTAIN_BULGE_PROB,
    },
  };
  struct wall_detector *wd = VEHICLE_LOCAL(wall_detector);
  wall_detector_filter_init(&wd->filter, &params);
  AbiBindMsgOBSTACLE_DETECTION(WALL_DETECTOR_OBSTACLE_SENDER_ID, &wd->obstacle_ev, wall_detector_obstacle_cb);
  AbiBindMsgRANGING_DISTANCE(WALL_DETECTOR_RANGING_SENDER_ID, &wd->ranging_ev, wall_detector_ranging_cb);
}
