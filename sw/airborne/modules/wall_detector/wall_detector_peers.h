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
 * The wall detector's table of ranged peers: the last ranging distances of each, and the peers that can explain an
 * echo now with the distance and prior odds the filter judges them by (the median of the fresh distances, the
 * prior odds on a sonar at that median).
 */

#ifndef WALL_DETECTOR_PEERS_H
#define WALL_DETECTOR_PEERS_H

#include "modules/wall_detector/wall_detector_reading.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Peers the filter tracks at once (when a new one appears the table replaces one, wall_detector_peers_record). */
#ifndef WALL_DETECTOR_MAX_PEERS
#define WALL_DETECTOR_MAX_PEERS 16
#endif

/** Ranging distances kept per peer: the filter judges echoes against the median of the fresh ones, which two
 * consecutive readings from the ranging error's tail (more than 0.5 m off: 0.8 % of the default mixture's
 * readings each) do not move; at 10 Hz it lags a moving peer by about 0.2 s. */
#define WALL_DETECTOR_PEER_HISTORY 5

/** The last ranging distances of one peer (a ring buffer). */
struct wall_detector_peer {
  bool used;                                      ///< the slot holds a peer (once used, it stays used: a new
                                                  ///< peer replaces its peer)
  uint16_t id;                                    ///< aircraft id of the peer
  uint8_t count;                                  ///< distances stored, up to WALL_DETECTOR_PEER_HISTORY
  uint8_t latest;                                 ///< index of the newest one
  float distance_m[WALL_DETECTOR_PEER_HISTORY];   ///< ranged distances [m]
  uint32_t stamp_us[WALL_DETECTOR_PEER_HISTORY];  ///< their times [us]
};

/** The peer slots. */
struct wall_detector_peers {
  struct wall_detector_peer slot[WALL_DETECTOR_MAX_PEERS];
};

/** The peers that can explain an echo now (wall_detector_peers_candidates), in slot order. */
struct wall_detector_candidates {
  unsigned nb;                                 ///< candidates
  int slot[WALL_DETECTOR_MAX_PEERS];           ///< their slots
  float distance_m[WALL_DETECTOR_MAX_PEERS];   ///< the median of their fresh distances [m]
  float newest_m[WALL_DETECTOR_MAX_PEERS];     ///< their newest distances (the baseline judges by these) [m]
  double prior_odds[WALL_DETECTOR_MAX_PEERS];  ///< their prior odds rho = pi / (1 - 4 pi) on one sonar, pi =
                                               ///< wall_detector_peer_prior at the median (filter header)
};

/** True for a time then_us that is at most timeout_s old at now_us (wall_detector_elapsed_s <= timeout_s). */
extern bool wall_detector_is_fresh(uint32_t then_us, uint32_t now_us, float timeout_s);

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
                                      uint32_t stamp_us, float ranging_max_m, float timeout_s, bool *is_new);

/**
 * The candidates at now_us: the peers whose newest distance is fresh (within timeout_s) and in range and the median
 * of whose fresh distances (the mean of the middle two for an even number) is in range.
 */
extern void wall_detector_peers_candidates(const struct wall_detector_peers *peers, uint32_t now_us, float timeout_s,
    const struct wall_detector_model *model, struct wall_detector_candidates *candidates);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_PEERS_H */
