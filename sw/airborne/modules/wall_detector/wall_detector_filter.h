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
 * Evidence. For each horizontal sonar s and each ranged peer k the filter keeps
 *   E_sk = sum over the sonar's readings of discounted log p(reading | echo from peer k) / p(reading | wall),
 * updated per reading as
 *   E_sk <- clamp(lambda E_sk + llr_k - g, -evidence_max, +evidence_max),
 *   lambda = exp(-dt / evidence_tau_s - ds / move_scale_m - |dpsi| / turn_scale_rad),
 * where dt, ds and dpsi are the time, the horizontal translation and the yaw change since the sonar's previous reading:
 * old evidence fades with time and faster when the copter moves or turns. llr_k (wall_detector_reading_llr; from the
 * model's shared table, within 1e-3: wall_detector_llr_table.h) weighs the reading against the peer's ranged distance
 * (the median of its last WALL_DETECTOR_PEER_HISTORY fresh distances) under the sonar and ranging error models, against
 * a wall at an unknown range; g (below) is what the wall this sonar remembers says about the reading. The bound keeps a
 * coincidence (a wall at a peer's echo range for a while) from outweighing a few readings unlike the peer. When the
 * echo jumps by more than jump_m from the previous echo, the sonar probably sees another target: each E_sk restarts
 * from 0 before the update, except where it favoured peer k (E_sk > 0) and the jump went between peer k's echo and its
 * cross-talk (wall_detector_reading_part), as when a facing copter's readings alternate.
 *
 * Static walls. A wall does not move and is a straight line: the sonar remembers the readings it judged walls,
 * as the wall's position along the boresight (reading + own position along it) against the copter's position
 * across it, a least-squares line over the last WALL_DETECTOR_TRACK_READINGS (its slope, the wall's
 * obliqueness, shrunk toward 0 until the copter has moved sideways by WALL_DETECTOR_TRACK_SPREAD). A later
 * reading of that wall is where the line predicts for the copter's present position, within track_sigma_m.
 * g = wall_detector_track_llr(reading, predicted, keep) is the log ratio of the wall hypothesis with that
 * prediction to a wall at an unknown range, keep = (1 - outlier_prob) exp(-dt / evidence_tau_s - lateral /
 * move_scale_m - |dpsi| / turn_scale_rad) (time, sideways motion and turn since the last remembered reading,
 * after which the beam may fall on another wall). An echo at the remembered wall is therefore a wall even while
 * a peer happens to be ranged at the same distance, and a copter drifting in front of the beam leaves the line
 * (the average lags it); an echo in front of it (a body between) gains evidence for the peers and does not
 * replace it while it is still half credible; one beyond it by more than WALL_DETECTOR_TRACK_GATE sd means the
 * remembered surface was no wall: it is forgotten.

 * Decision: a joint assignment. Each sonar sees one target (the nearest: a wall or one peer) and each peer is on
 * one sonar at most (two boresights 90 degrees apart cannot both hit a body that does not overlap this one).
 * With prior odds rho_k = pi_k / (1 - 4 pi_k) that peer k is on a given sonar (pi_k = wall_detector_peer_prior,
 * the fraction of bearings at which a boresight hits it) and weights w_ok = rho_k exp(E_ok) (w = 1 for a wall),
 * the posterior odds that sonar s sees a copter sum over the assignments A of the other sonars to walls and
 * distinct peers:
 *   L = log( sum_A prod_{o != s} w_{o,A(o)} sum_{k not in A} w_sk ) - log( sum_A prod_{o != s} w_{o,A(o)} )
 * (L = -infinity with no peer in range; wall_detector_assignment_log_odds). A peer that another sonar tracks
 * better explains little here; several sonars seeing copters share the peers in range among them. The reading is
 * a wall when L <= -wall_threshold, a copter when L >= copter_threshold, else unknown (L in float; the filter
 * compares the odds exp(L) with bounds of the thresholds and takes the log only within 1e-6 of one:
 * wall_detector_odds_band).
 * Pure functions over the state struct; time and pose are passed in. The state also caches what only changes
 * when the model, a peer's distances or a sonar's evidence change (the model's constants, the peers in range with
 * their median and prior odds, exp(E_sk), the weights w_ok with their sums over assignments
 * and each sonar's L); each cache entry carries what it was computed from and is recomputed when that differs, so
 * the decisions are the same as without it. A reading whose peers in range are all surely held at the lower bound
 * (wall_detector_filter_surely_pinned, from cheap bounds) computes neither its discount nor g: they could not change
 * the evidence. The peer table is wall_detector_peers.h, the sum over assignments wall_detector_assignment.h.
 */

#ifndef WALL_DETECTOR_FILTER_H
#define WALL_DETECTOR_FILTER_H

#include "modules/wall_detector/wall_detector_assignment.h"
#include "modules/wall_detector/wall_detector_llr_table.h"
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
  float evidence_max;      ///< bound of each peer's evidence [log-likelihood ratio], at most 100 (the
                           ///< assignment multiplies four exp(E) unscaled)
  float wall_threshold;    ///< wall when the log-odds is at or below -wall_threshold
  float copter_threshold;  ///< copter when the log-odds is at or above copter_threshold
  float peer_timeout_s;    ///< ranging older than this is ignored [s]
  float baseline_eps_m;    ///< tolerance of the single-reading baseline [m]
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
  bool started;                               ///< a reading has been seen
  uint32_t stamp_us;                          ///< time of the previous reading [us]
  struct wall_detector_pose pose;             ///< pose at the previous reading
  float range_m;                              ///< previous echo (reading below the maximum) [m]
  bool wall_known;                            ///< a wall is remembered
  float wall_along_m;                         ///< mean of reading + position along the boresight [m]
  float wall_lateral_m;                       ///< mean position across the boresight at those readings [m]
  float wall_lateral_var_m2;                  ///< variance of that position [m^2]
  float wall_cov_m2;                          ///< covariance of the two [m^2]
  uint16_t wall_readings;                     ///< readings averaged, up to WALL_DETECTOR_TRACK_READINGS
  float wall_last_lateral_m;                  ///< position across the boresight at the last reading averaged [m]
  float wall_last_yaw_rad;                    ///< heading at the last reading averaged [rad]
  uint32_t wall_stamp_us;                     ///< time of the last reading averaged [us]
  struct wall_detector_bearing boresight;     ///< cache: the boresight's bearing, its sine (east) and cosine (north)
};

/**
 * Cache of the decision: the weights w_ok = rho_k exp(E_ok) of the peers in range, each with the prior odds and
 * evidence it is of, and what was found from them. Between two readings of a sonar usually only its own evidence
 * changes, and often none (evidence at a bound): an entry is recomputed when its peer, prior or evidence differs,
 * the sums over assignments when any weight was, L and the confidence of a sonar when the sums were.
 */
struct wall_detector_decision_cache {
  unsigned peer_nb;                                                ///< peers in range the weights are of
  uint32_t listing_of;                                             ///< the listing of the peers in range
                                                                   ///< (candidates_listing) the rows are of
  int slot[WALL_DETECTOR_MAX_PEERS];                               ///< their slots
  double prior_odds[WALL_DETECTOR_MAX_PEERS];                      ///< their prior odds rho_k
  float evidence[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];  ///< E_ok of each weight
  double weight[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];   ///< w_ok
  bool summed;                                                     ///< `sum` is of these weights
  double sum[WALL_DETECTOR_SONAR_SETS];                            ///< wall_detector_assignment_sums of them
  bool found[WALL_DETECTOR_SONAR_NB];                              ///< odds and confidence of a sonar are of
                                                                   ///< `sum`
  double odds[WALL_DETECTOR_SONAR_NB];                             ///< exp(L) per sonar
  float confidence[WALL_DETECTOR_SONAR_NB];                        ///< 1 / (1 + exp(-|L|)) per sonar
};

/** The fading rates of the evidence and of a remembered wall, the reciprocals of the scales: a reading multiplies
 * by them where the law (file comment) divides by the scales. */
struct wall_detector_fade {
  float per_s;     ///< 1 / evidence_tau_s [1/s]
  float per_m;     ///< 1 / move_scale_m [1/m]
  float per_rad;   ///< 1 / turn_scale_rad [1/rad]
};

/** The whole filter state of one copter. */
struct wall_detector_filter {
  struct wall_detector_params params;
  struct wall_detector_params settings_of;  ///< cache: the params that terms, age_limit_us, fade and the odds bands
                                            ///< were brought up to (one comparison per reading)
  struct wall_detector_model_terms terms;  ///< cache: constants of the model terms.model (params.model when current)
  const struct wall_detector_llr_table *llr_table;  ///< the shared table of terms.model, NULL: the exact llr
  float age_limit_of_s;                    ///< cache: the timeout age_limit_us is of [s]
  int64_t age_limit_us;                    ///< cache: wall_detector_fresh_age_limit_us(age_limit_of_s) [us]
  struct wall_detector_fade fade;          ///< cache: the fading rates of the params' scales
  struct wall_detector_odds_band wall_band;    ///< cache: the odds band of -wall_threshold
  struct wall_detector_odds_band copter_band;  ///< cache: the odds band of copter_threshold
  struct wall_detector_peers peers;
  struct wall_detector_sonar sonars[WALL_DETECTOR_SONAR_NB];
  /** E_sk per peer slot k and sonar s [log-likelihood ratio] (a peer's four side by side: the decision reads them
   * together); 0 in a slot holding no peer (filter_ranging clears a slot's evidence when a peer takes it) */
  float evidence[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];
  float exp_of[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];  ///< cache: the evidence exp_evidence is of
  double exp_evidence[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];  ///< cache: exp(exp_of), 0: not computed
  struct wall_detector_decision_cache decision;  ///< cache: the weights and what was found from them
};

/** The verdict on one reading. */
struct wall_detector_decision {
  enum wall_detector_class target_class;    ///< the filter's class
  float confidence;                         ///< posterior of the likelier class: 1/(1+exp(-|L|)), 0.5..1
  double odds;                              ///< exp(L), posterior odds of copter against wall (0: no peer; 1: no
                                            ///< echo); L is wall_detector_decision_log_odds
  float attraction_m;                       ///< the reading when the class is copter, else -1 [m]
  float repulsion_m;                        ///< always the reading [m]
  enum wall_detector_class baseline_class;  ///< the single-reading check on the same reading
};

/** L of a verdict, the posterior log-odds of copter against wall (-infinity: no peer), (float)log(odds): the
 * filter decides without it (wall_detector_log_odds_at_most and _at_least compare the odds). */
extern float wall_detector_decision_log_odds(const struct wall_detector_decision *decision);

/** Start with no peers and no evidence. */
extern void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params);

/**
 * Record a ranging distance. A distance at or above the ranging maximum is dropped while the peer's newest
 * distance is in range and fresh (within peer_timeout_s): the error's tail reaches the maximum; a peer that
 * really left stops being a candidate when its distances go stale. A peer out of range that is not in the table
 * takes no slot, and a new peer replaces first a peer that cannot explain an echo (stale or out of range): in a
 * dense swarm the many peers beyond the range must not push the near ones out of the WALL_DETECTOR_MAX_PEERS
 * slots.
 * @return the peer's slot, or -1 for a non-finite or negative distance or an out-of-range peer not in the table
 *         (ignored)
 */
extern int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                        uint32_t stamp_us);

/**
 * The llr the filter weighs a reading with against a peer at peer_distance_m (wall_detector_reading_llr): from
 * the model's shared table (wall_detector_llr_table.h, within its error_bound; its clamped-reading table for a
 * reading at the minimum) when the filter has one, else exact.
 */
extern float wall_detector_filter_reading_llr(const struct wall_detector_filter *filter, float range_m,
    float peer_distance_m);

/**
 * The factor lambda by which a sonar's evidence is discounted before a reading (time, translation, turn; see the
 * file comment), 0 before the sonar's first reading.
 */
extern float wall_detector_filter_discount(const struct wall_detector_params *params,
    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose, uint32_t now_us);

/**
 * True when the pinning test of a reading (update_evidence: a peer's evidence stays at -evidence_max when
 * (lambda E + llr_bound) - g <= -evidence_max, for g > 0 and a reading above the minimum) surely passes for evidence
 * E, whatever lambda = expf(discount_exp) and g = wall_detector_track_llr(range_m, predicted_m,
 * keep = (1 - outlier_prob) expf(keep_exp)) are exactly. Found from lower bounds of lambda (wall_detector_bounds.h)
 * and of g (log(keep ratio), a sum of the exponents), without expf or logf: a reading whose peers in range are all
 * surely pinned needs neither (float rounding is monotone: a test passed with a larger lambda E and a smaller g is
 * passed with the exact ones).
 * False also for an exponent above 0 or NaN.
 */
extern bool wall_detector_filter_surely_pinned(const struct wall_detector_filter *filter, float evidence,
    float range_m, float predicted_m, float discount_exp, float keep_exp);

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
 * Where the wall a sonar remembers should read now (file comment), and the probability keep that a wall echo
 * comes from it.
 * @return false when the sonar remembers no wall
 */
extern bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep);

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
