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
 * @file modules/wall_detector/wall_detector_peers.h
 * The wall detector's table of ranged peers: the last ranging distances of each, and what the filter judges an
 * echo of that peer with (the median of its fresh distances, its prior odds on a sonar), cached until the distances
 * or the model change. The newest time and distance of every slot sit in one compact table, so the per-reading scan
 * for candidates reads a few cache lines only.
 */

#ifndef WALL_DETECTOR_PEERS_H
#define WALL_DETECTOR_PEERS_H

#include "modules/wall_detector/wall_detector_reading.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Peers the filter tracks at once (the stalest one is replaced when a new one appears). */
#ifndef WALL_DETECTOR_MAX_PEERS
#define WALL_DETECTOR_MAX_PEERS 8
#endif

/** Ranging distances kept per peer: the filter judges echoes against the median of the fresh ones, which two
 * consecutive readings from the ranging error's tail (more than 0.5 m off: 0.8 % of the default mixture's
 * readings each) do not move; at 10 Hz it lags a moving peer by about 0.2 s. */
#define WALL_DETECTOR_PEER_HISTORY 5

/** The last ranging distances of one peer (a ring buffer), and what the filter derived from them. */
struct wall_detector_peer {
  uint8_t count;                                  ///< distances stored, up to WALL_DETECTOR_PEER_HISTORY
  uint8_t latest;                                 ///< index of the newest one
  uint8_t median_of;                              ///< cache: distances median_m is of (bit i: distance_m[i]),
                                                  ///< 0 when none (a new distance empties the cache)
  uint8_t fresh;                                  ///< cache: the fresh distances (bit i: distance_m[i]), the same
                                                  ///< from fresh_at_us for fresh_for_us
  uint32_t fresh_at_us;                           ///< cache: when `fresh` was found [us]
  uint32_t fresh_for_us;                          ///< cache: how long `fresh` holds, 0: not found [us]
  float median_m;                                 ///< cache: their median [m]
  float distance_m[WALL_DETECTOR_PEER_HISTORY];   ///< ranged distances [m]
  uint32_t stamp_us[WALL_DETECTOR_PEER_HISTORY];  ///< their times [us]
  double prior_odds;                              ///< cache: rho = pi / (1 - 4 pi) at median_m (filter header),
                                                  ///< NAN: none
};

/** The peers that can explain an echo now (heard within the timeout, in range), as the filter judges them. */
struct wall_detector_candidates {
  unsigned nb;                                 ///< candidates, in slot order
  unsigned slot_set;                           ///< their slots as a set (bit k: slot k)
  int slot[WALL_DETECTOR_MAX_PEERS];           ///< their slots
  float distance_m[WALL_DETECTOR_MAX_PEERS];   ///< the median of their fresh distances (cached) [m]
  float newest_m[WALL_DETECTOR_MAX_PEERS];     ///< their newest distances (the baseline judges by these) [m]
  double prior_odds[WALL_DETECTOR_MAX_PEERS];  ///< their prior odds rho on one sonar at the median (cached)
};

/** The peer slots: who is in each and its newest distance (compact), then each slot's history and caches. */
struct wall_detector_peers {
  uint32_t used_slots;                               ///< the slots holding a peer (bit k: slot k); a slot once
                                                     ///< used stays used (a new peer replaces its peer)
  uint16_t id[WALL_DETECTOR_MAX_PEERS];              ///< aircraft id of the peer
  uint32_t newest_stamp_us[WALL_DETECTOR_MAX_PEERS];  ///< time of its newest distance [us]
  float newest_m[WALL_DETECTOR_MAX_PEERS];           ///< its newest distance [m]
  uint32_t candidates_at_us;                         ///< cache: when `candidates` were listed [us]
  uint32_t candidates_for_us;                        ///< cache: how long they hold (until the first peer's fresh
                                                     ///< distances change), 0: not listed [us]
  struct wall_detector_candidates candidates;        ///< cache: the candidates (wall_detector_peers_candidates)
  uint32_t candidates_listing;                       ///< listings of `candidates` so far (changed only by a
                                                     ///< listing: a cache of them keeps it to know they are the
                                                     ///< same; 0: none yet)
  struct wall_detector_peer slot[WALL_DETECTOR_MAX_PEERS];
};

/** True when slot k holds a peer. */
static inline bool wall_detector_peers_slot_used(const struct wall_detector_peers *peers, int k)
{
  return (peers->used_slots >> k) & 1u;
}

/**
 * The largest age (int32_t)(now_us - then_us) [us] that counts as within timeout_s: a time is fresh when
 * (float)age x 1e-6 <= timeout_s, i.e. exactly when the age is at most this (INT32_MIN - 1 when no age is, e.g. for
 * a NaN timeout). Lets the per-reading loops compare integers.
 */
extern int64_t wall_detector_fresh_age_limit_us(float timeout_s);

/** True for a time at most age_limit_us (wall_detector_fresh_age_limit_us) old at now_us. */
static inline bool wall_detector_is_fresh(uint32_t then_us, uint32_t now_us, int64_t age_limit_us)
{
  return (int32_t)(now_us - then_us) <= age_limit_us;
}

/**
 * Record a ranging distance (wall_detector_filter_ranging: a distance at or above ranging_max_m is dropped while
 * the peer's newest distance is in range and fresh, and when the peer is not in the table). A new peer takes a
 * free slot, else the slot of the peer heard longest ago among those that cannot explain an echo (stale or out
 * of range), else the slot of the peer heard longest ago.
 * @param[out] is_new true when the peer took a slot that held no peer or another one (the caller drops the
 *             slot's evidence)
 * @return the peer's slot, or -1 when a peer not in the table is out of range (nothing recorded)
 */
extern int wall_detector_peers_record(struct wall_detector_peers *peers, uint16_t peer_id, float distance_m,
                                      uint32_t stamp_us, float ranging_max_m, int64_t age_limit_us, bool *is_new);

/**
 * The candidates at now_us: the peers heard within the timeout whose newest distance and the median of whose fresh
 * distances are within the ranging range. Listed again only when they may have changed: after a distance was
 * recorded, the model or the timeout changed, or a peer's fresh distances changed (a distance went stale; the
 * time is known when they are listed), so the per-reading cost is a time comparison. Each listing counts in
 * candidates_listing: while the count is the same, so is the list.
 * @return the list, in the table's cache (valid until the next call)
 */
extern const struct wall_detector_candidates *wall_detector_peers_candidates(struct wall_detector_peers *peers,
    uint32_t now_us, int64_t age_limit_us, const struct wall_detector_model *model);

/** Drop what was derived from the timeout (the fresh distances), after it changed. */
extern void wall_detector_peers_timeout_changed(struct wall_detector_peers *peers);

/** Drop what was derived from the model (the prior odds), after the model changed. */
extern void wall_detector_peers_model_changed(struct wall_detector_peers *peers);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_PEERS_H */
