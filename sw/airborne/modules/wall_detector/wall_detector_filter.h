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
 * For each horizontal sonar and each ranged peer k the filter keeps the evidence
 *   E_k = sum over the sonar's readings of discounted log p(reading | echo from peer k) / p(reading | wall)
 * (wall_detector_reading_llr, with the median of the peer's last WALL_DETECTOR_PEER_HISTORY fresh ranging
 * distances), updated per reading as
 *   E_k <- clamp(lambda * E_k + llr_k, -evidence_max, +evidence_max),
 *   lambda = exp(-dt / evidence_tau_s - ds / move_scale_m - |dpsi| / turn_scale_rad),
 * where dt, ds and dpsi are the time, the horizontal translation and the yaw change since the sonar's previous
 * reading: old evidence fades with time and faster when the copter moves or turns. When the echo jumps by
 * more than jump_m from the previous echo, the sonar probably sees another target: each E_k restarts from 0
 * before the update, except where it favoured peer k (E_k > 0) and the new reading is more likely peer k's echo
 * or cross-talk than an outlier (llr_k > log(2 outlier_prob)), as when a facing copter's echo and cross-talk
 * alternate. A peer is on one sonar at most (a body of radius r is hit by two boresights 90 degrees apart only
 * within sqrt(2) r of the centre), so for peers ranged beyond sqrt(2) copter_offset_m + 2 ranging_sigma_m the
 * best claim of the other sonars on the same peer is taken off:
 *   E'_k = E_k - max(0, max_{o != this sonar} E_{o,k})
 * (a peer another sonar tracks well explains nothing here; two sonars claiming it equally are both left
 * undecided about it; sonars without evidence for it change nothing); closer peers keep E'_k = E_k. The
 * sonar's log-odds of "copter" against "wall" is that of "these echoes come from one of the K peers in range,
 * each equally likely":
 *   L = log(sum_k exp(E'_k)) - log K     (L = -evidence_max when no peer is in range),
 * and the reading is a wall when L <= -wall_threshold, a copter when L >= copter_threshold, else unknown.
 * Pure functions over the state struct; time and pose are passed in.
 */

#ifndef WALL_DETECTOR_FILTER_H
#define WALL_DETECTOR_FILTER_H

#include "modules/wall_detector/wall_detector_reading.h"

/** Horizontal sonars: front, right, back, left (indices 0..3). */
#define WALL_DETECTOR_SONAR_NB 4

/** Peers the filter tracks at once (the stalest one is replaced when a new one appears). */
#ifndef WALL_DETECTOR_MAX_PEERS
#define WALL_DETECTOR_MAX_PEERS 8
#endif

/** Model and thresholds of the filter (each mirrors a WALL_DETECTOR_* define and a setting). */
struct wall_detector_params {
  struct wall_detector_model model;  ///< sonar and ranging error models
  float evidence_tau_s;    ///< time constant of the evidence decay [s]
  float move_scale_m;      ///< translation over which evidence fades by 1/e [m]
  float turn_scale_rad;    ///< yaw change over which evidence fades by 1/e [rad]
  float jump_m;            ///< an echo this far from the previous echo restarts the evidence [m]
  float evidence_max;      ///< bound of each peer's evidence [log-likelihood ratio]
  float wall_threshold;    ///< wall when the log-odds is at or below -wall_threshold
  float copter_threshold;  ///< copter when the log-odds is at or above copter_threshold
  float peer_timeout_s;    ///< ranging older than this is ignored [s]
  float baseline_eps_m;    ///< tolerance of the single-reading baseline [m]
};

/** Where the copter is, in any fixed horizontal frame (only differences are used). */
struct wall_detector_pose {
  float x_m;      ///< position [m]
  float y_m;      ///< position [m]
  float yaw_rad;  ///< heading [rad]
};

/** Ranging distances kept per peer: the filter judges echoes against their median, which a single reading
 * from the ranging error's tail does not move. */
#define WALL_DETECTOR_PEER_HISTORY 3

/** The last ranging distances of one peer (a ring buffer). */
struct wall_detector_peer {
  bool used;                                      ///< slot holds a peer
  uint16_t id;                                    ///< aircraft id of the peer
  uint8_t count;                                  ///< distances stored, up to WALL_DETECTOR_PEER_HISTORY
  uint8_t latest;                                 ///< index of the newest one
  float distance_m[WALL_DETECTOR_PEER_HISTORY];   ///< ranged distances [m]
  uint32_t stamp_us[WALL_DETECTOR_PEER_HISTORY];  ///< their times [us]
};

/** Evidence of one sonar. */
struct wall_detector_sonar {
  bool started;                               ///< a reading has been seen
  uint32_t stamp_us;                          ///< time of the previous reading [us]
  struct wall_detector_pose pose;             ///< pose at the previous reading
  float range_m;                              ///< previous echo (reading below the maximum) [m]
  float evidence[WALL_DETECTOR_MAX_PEERS];    ///< E_k per peer slot [log-likelihood ratio]
};

/** The whole filter state of one copter. */
struct wall_detector_filter {
  struct wall_detector_params params;
  struct wall_detector_peer peers[WALL_DETECTOR_MAX_PEERS];
  struct wall_detector_sonar sonars[WALL_DETECTOR_SONAR_NB];
};

/** The verdict on one reading. */
struct wall_detector_decision {
  enum wall_detector_class target_class;    ///< the filter's class
  float confidence;                         ///< likelier class's posterior (even priors): 1/(1+exp(-|L|)), 0.5..1
  float log_odds;                           ///< L, log-odds of copter against wall
  float attraction_m;                       ///< the reading when the class is copter, else -1 [m]
  float repulsion_m;                        ///< always the reading [m]
  enum wall_detector_class baseline_class;  ///< the single-reading check on the same reading
};

/** Start with no peers and no evidence. */
extern void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params);

/**
 * Record a ranging distance. A distance at or above the ranging maximum is dropped while the peer's newest
 * distance is in range and fresh (within peer_timeout_s): the error's tail reaches the maximum; a peer that
 * really left stops being a candidate when its distances go stale.
 * @return the peer's slot, or -1 for a non-finite or negative distance (ignored)
 */
extern int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                        uint32_t stamp_us);

/**
 * The factor lambda by which a sonar's evidence is discounted before a reading (time, translation, turn; see the
 * file comment), 0 before the sonar's first reading.
 */
extern float wall_detector_filter_discount(const struct wall_detector_params *params,
    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose, uint32_t now_us);

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

#endif /* WALL_DETECTOR_FILTER_H */
