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
 * @file modules/wall_detector/wall_detector_filter.h
 * Wall or copter, judged from a sequence of sonar readings (the proposal of the lab report, section 4.6).
 *
 * Evidence. For each horizontal sonar s and each ranged peer k the filter keeps the evidence E_sk, the discounted
 * sum over the sonar's readings of log p(reading | echo from peer k) - log p(reading | wall). An echo updates it as
 *   E_sk <- clamp(lambda E_sk + llr_k - g, -evidence_max, +evidence_max),
 *   lambda = exp(-dt / evidence_tau_s - ds / move_scale_m - |dpsi| / turn_scale_rad),
 * dt, ds and dpsi being the time, the horizontal translation and the yaw change since the sonar's previous reading
 * (lambda = 0 before its first one): old evidence fades with time, and faster when the copter moves or turns. A
 * reading without echo only discounts. llr_k (wall_detector_reading_llr) weighs the reading against the peer's
 * ranged distance (the median of its fresh distances, wall_detector_peers.h) under the sonar and ranging error
 * models, against a wall at an unknown range; g is what the remembered walls say about the reading
 * (below). The clamp keeps a coincidence (a wall at a peer's echo range for a while) from outweighing a few
 * readings unlike the peer.
 *
 * Jump. When the echo is more than jump_m from the sonar's previous echo, the sonar probably sees another target:
 * each E_sk restarts from 0 before the update, except where it favoured peer k (E_sk > 0) and the jump went between
 * peer k's echo (wall_detector_reading_part of the longer reading) and a shorter reading: its cross-talk, read
 * (path + c dt) / 2 before the echo whatever the trigger offset dt of the two rings, or a short reading, as when a
 * facing copter's readings alternate between its echo and its cross-talk.
 *
 * Two memories of the walls, and g. A wall does not move and is a straight line. The copter remembers the walls for
 * the whole flight in a map: lines in the frame of its position estimate, learned from the echoes of all four
 * sonars, following the estimate's drift, and told from bodies that stay still (wall_detector_map.h). Each sonar
 * also remembers the wall it saw over the last 2 s (below): a curtain that bulged toward the copter and stays so, a
 * wall the map does not know yet. g is the log ratio of "a wall, the one the map predicts on this beam or the one
 * the sonar saw, with equal weight" to "a wall at an unknown range":
 *   g = log( (exp(g_map) + exp(g_sonar)) / 2 ),
 * g_map = log wall_detector_map_ratio (0 where the map knows no wall), g_sonar the sonar's (0 where it remembers
 * none).
 * An echo at a remembered wall is a wall even in a crowd of peers ranged at its distance; an echo in front of both
 * (beyond what a curtain bulges) gains evidence for the peers. With use_map false g = g_sonar: the law before the
 * map, kept for comparison.
 *
 * The wall a sonar remembers, g_sonar. The sonar remembers the readings it judged walls, as the wall's position
 * along the boresight (reading + own position along it) against the copter's position across it, a least-squares
 * line over the last WALL_DETECTOR_TRACK_READINGS (its slope, the wall's obliqueness, shrunk toward 0 until the
 * copter has moved sideways by WALL_DETECTOR_TRACK_SPREAD). The wall should read where the line predicts for the
 * copter's present position, within track_sigma_m, and
 *   g_sonar = log wall_detector_track_ratio(reading, predicted, keep),
 *   keep = (1 - outlier_prob) exp(-dt / evidence_tau_s - lateral / move_scale_m - |dpsi| / turn_scale_rad),
 * the log ratio of "a wall, the remembered one with probability keep" to "a wall at an unknown range" (dt, lateral
 * and dpsi: the time, sideways motion and turn since the last remembered reading, after which the beam may fall on
 * another wall); g_sonar = 0 while no wall is remembered. A copter drifting in front of the beam leaves the line
 * (the average lags it). An echo in front of the line (a body between) gains evidence for the peers and does not
 * replace the wall while it is still half credible (keep above half its most); one beyond it by more than
 * WALL_DETECTOR_TRACK_GATE sd shows the remembered surface was no wall: it is forgotten (after this reading's g).
 *
 * Decision: a joint assignment. Each sonar sees one target (the nearest: a wall or one peer) and each peer is on
 * one sonar at most (two boresights 90 degrees apart cannot both hit a body that does not overlap this one).
 * With prior odds rho_k = pi_k / (1 - 4 pi_k) that peer k is on a given sonar (pi_k = wall_detector_peer_prior,
 * the fraction of bearings at which a boresight hits it) and weights w_ok = rho_k exp(E_ok) (w = 1 for a wall),
 * the posterior log-odds that sonar s sees a copter sum over the assignments A of the other sonars to walls and
 * distinct peers:
 *   L = log( sum_A prod_{o != s} w_{o,A(o)} sum_{k not in A} w_sk ) - log( sum_A prod_{o != s} w_{o,A(o)} )
 * (L = -infinity with no peer in range; wall_detector_assignment.h). A peer that another sonar tracks better
 * explains little here; several sonars seeing copters share the peers in range among them. The reading is a wall
 * when L <= -wall_threshold (and is then remembered), a copter when L >= copter_threshold, else unknown (L in float).
 *
 * Settings. The params are the module's settings, changed at run time from the ground station: every reading uses
 * them as they are, and the model's constants and llr table are looked up again when the model changed.
 *
 * Cost of one echo, worst case (P = WALL_DETECTOR_MAX_PEERS = 16 peers in range; single-precision FPU, as a
 * Cortex-M4F): the discount and the remembered wall's keep, 2 expf, 1 sqrtf, 2 remainderf; the boresight, 2 sinf
 * and 2 cosf; g, 1 expf and 1 logf; the wall map, wall_detector_map.h (two passes over its 8 lines, a sinf and a
 * cosf); the peers in range, P medians of 5 and P asinf; the evidence, P llr (the shared table: 2 lookups and 1 logf
 * each); the weights, 4 P = 64 expf; the sums over the 16 sets of sonars, 32 P = 512 double multiply-adds (software
 * double on a Cortex-M4), then 16 additions, a division and a log in double. A jump adds P
 * wall_detector_reading_part (in double: 3 exp and an erfc each).
 */

#ifndef WALL_DETECTOR_FILTER_H
#define WALL_DETECTOR_FILTER_H

#include "modules/wall_detector/wall_detector_assignment.h"
#include "modules/wall_detector/wall_detector_llr_table.h"
#include "modules/wall_detector/wall_detector_map.h"
#include "modules/wall_detector/wall_detector_peers.h"
#include "modules/wall_detector/wall_detector_pose.h"
#include "modules/wall_detector/wall_detector_reading.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Model and thresholds of the filter (each mirrors a WALL_DETECTOR_* define and a setting). */
struct wall_detector_params {
  struct wall_detector_model model;  ///< sonar and ranging error models
  float evidence_tau_s;    ///< time constant of the evidence decay [s]
  float move_scale_m;      ///< translation over which evidence fades by 1/e [m]
  float turn_scale_rad;    ///< yaw change over which evidence fades by 1/e [rad]
  float jump_m;            ///< an echo this far from the previous echo restarts the evidence [m]
  float evidence_max;      ///< bound of each peer's evidence [log-likelihood ratio], at most 80 (the
                           ///< decision's expf(E) is finite below 88)
  float wall_threshold;    ///< wall when the log-odds is at or below -wall_threshold
  float copter_threshold;  ///< copter when the log-odds is at or above copter_threshold
  float peer_timeout_s;    ///< ranging older than this is ignored [s]
  float baseline_eps_m;    ///< tolerance of the single-reading baseline [m]
  bool use_map;            ///< g from the wall map (wall_detector_map.h) and each sonar's remembered wall, else from
                           ///< the latter alone
  struct wall_detector_map_params map;  ///< the wall map's parameters
};

/** A reading this many track sd beyond the remembered wall shows that it was no wall; one this far off it starts
 * a new one (3: 0.13 % of a wall's readings fall farther on one side). */
#define WALL_DETECTOR_TRACK_GATE 3.f

/** Readings averaged into a remembered wall (2 s at 20 Hz): the mean of a surface drifting at v lags it by about
 * v x 2 s, so a copter moving at 0.075 m/s or more leaves the gate (3 x 0.05 m), while the wall's reading noise
 * and the curtain's sway (a few cm, back and forth) average out. */
#ifndef WALL_DETECTOR_TRACK_READINGS
#define WALL_DETECTOR_TRACK_READINGS 40
#endif

/** Sideways spread of the copter's positions over a remembered wall's readings below which the wall is taken as
 * square to the beam [m]: its slope, fitted from the readings, counts only once the copter has moved sideways by
 * more than this (0.1 m: two track sd). */
#define WALL_DETECTOR_TRACK_SPREAD 0.1f

/** What one sonar remembers (its evidence per peer is the filter's evidence[k][s]). */
struct wall_detector_sonar {
  bool started;                    ///< a reading has been seen
  uint32_t stamp_us;               ///< time of the previous reading [us]
  struct wall_detector_pose pose;  ///< pose at the previous reading
  float range_m;                   ///< previous echo (reading below the maximum) [m]
  bool wall_known;                 ///< a wall is remembered
  float wall_along_m;              ///< mean of reading + position along the boresight [m]
  float wall_lateral_m;            ///< mean position across the boresight at those readings [m]
  float wall_lateral_var_m2;       ///< variance of that position [m^2]
  float wall_cov_m2;               ///< covariance of the two [m^2]
  uint16_t wall_readings;          ///< readings averaged, up to WALL_DETECTOR_TRACK_READINGS
  float wall_last_lateral_m;       ///< position across the boresight at the last reading averaged [m]
  float wall_last_yaw_rad;         ///< heading at the last reading averaged [rad]
  uint32_t wall_stamp_us;          ///< time of the last reading averaged [us]
};

/** The whole filter state of one copter. */
struct wall_detector_filter {
  struct wall_detector_params params;      ///< the settings
  struct wall_detector_model_terms terms;  ///< constants of the model terms.model (params.model, after a reading)
  const struct wall_detector_llr_table *llr_table;  ///< the shared table of terms.model, NULL: the exact llr
  struct wall_detector_peers peers;
  struct wall_detector_sonar sonars[WALL_DETECTOR_SONAR_NB];
  struct wall_detector_map map;             ///< the walls remembered for the flight (params.use_map)
  /** E_sk per peer slot k and sonar s [log-likelihood ratio]; 0 in a slot holding no peer (filter_ranging clears a
   * slot's evidence when a peer takes it) */
  float evidence[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];
};

/** The verdict on one reading. */
struct wall_detector_decision {
  enum wall_detector_class target_class;    ///< the filter's class
  float confidence;                         ///< posterior of the likelier class: 1/(1+exp(-|L|)), 0.5..1
  double odds;                              ///< exp(L), posterior odds of copter against wall (0: no peer; 1: no
                                            ///< echo)
  float attraction_m;                       ///< the reading when the class is copter, else -1 [m]
  float repulsion_m;                        ///< always the reading [m]
  enum wall_detector_class baseline_class;  ///< the single-reading check on the same reading
};

/** L of a verdict, the posterior log-odds of copter against wall (-infinity: no peer), (float)log(odds). */
extern float wall_detector_decision_log_odds(const struct wall_detector_decision *decision);

/** Start with no peers and no evidence. */
extern void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params);

/**
 * Record a ranging distance (wall_detector_peers_record: a distance at or above the ranging maximum is dropped
 * while the peer's newest distance is in range and fresh, and for a peer not in the table; a new peer replaces
 * first a peer that cannot explain an echo). A peer that takes a slot starts with no evidence.
 * @return the peer's slot, or -1 for a non-finite or negative distance or an out-of-range peer not in the table
 */
extern int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                        uint32_t stamp_us);

/** The llr the filter weighs a reading with against a peer at peer_distance_m (wall_detector_reading_llr): from the
 * model's shared table (wall_detector_llr_table.h, within its error_bound) when there is one, else exact. */
extern float wall_detector_filter_reading_llr(const struct wall_detector_filter *filter, float range_m,
    float peer_distance_m);

/** The factor lambda by which a sonar's evidence is discounted before a reading (file comment). */
extern float wall_detector_filter_discount(const struct wall_detector_params *params,
    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose, uint32_t now_us);

/** Where the wall a sonar remembers should read now and the probability keep that a wall echo comes from it (file
 * comment); false when the sonar remembers no wall. */
extern bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep);

/**
 * Judge one reading of sonar `sonar` and update its evidence.
 * @param range_m the reading [m]; at or above the sonar maximum it is "no echo" (discounts, adds no evidence,
 *        and is not the "previous echo" of the jump test)
 * @return 0, or -1 (nothing changed) for a sonar index out of range or a non-finite or negative reading
 */
extern int wall_detector_filter_sonar(struct wall_detector_filter *filter, int sonar, float range_m,
                                      const struct wall_detector_pose *pose, uint32_t now_us,
                                      struct wall_detector_decision *decision);

/**
 * Sonar index of a body-frame heading (Paparazzi's: a yaw from the nose, clockwise seen from above):
 * the nearest of front (0 rad), right (pi/2), back (pi), left (-pi/2).
 * @return 0..3, or -1 for a non-finite heading
 */
extern int wall_detector_sonar_index(float heading_rad);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_FILTER_H */
