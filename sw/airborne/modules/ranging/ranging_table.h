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
 * @file modules/ranging/ranging_table.h
 * The newest distance to each peer, by aircraft id, with its age: what the wall detector and the swarm read.
 * Bounded: at most RANGING_TABLE_MAX_PEERS peers; the peer heard longest ago is replaced when full.
 * Pure logic: the caller passes the time in.
 */

#ifndef RANGING_TABLE_H
#define RANGING_TABLE_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Peers one copter keeps track of (the SwarmLab flies a handful; the benchmark swarms see few at a time) */
#ifndef RANGING_TABLE_MAX_PEERS
#define RANGING_TABLE_MAX_PEERS 32
#endif

struct ranging_peer {
  uint16_t id;         ///< aircraft id (0 = unused entry)
  float distance_m;    ///< newest distance [m]
  uint32_t stamp_us;   ///< when it was measured [us]
  uint32_t count;      ///< distances received from this peer
};

/** Slots of the look-up hint (a power of two): peer ids that differ modulo this never share a hint. */
#define RANGING_TABLE_HINTS 64

struct ranging_table {
  struct ranging_peer peers[RANGING_TABLE_MAX_PEERS];
  uint8_t hint[RANGING_TABLE_HINTS];  ///< per id modulo RANGING_TABLE_HINTS: the entry that id last went to
                                      ///< (checked before use; a look-up that misses it scans all entries)
  uint32_t stale_after_us;  ///< a distance older than this is not fresh
};

extern void ranging_table_init(struct ranging_table *t, uint32_t stale_after_us);
/** Store a distance; returns the peer's entry. */
extern const struct ranging_peer *ranging_table_update(struct ranging_table *t, uint16_t peer_id, float distance_m,
                                                       uint32_t stamp_us);
/** The entry of a peer, or NULL if it was never heard (or was replaced). */
extern const struct ranging_peer *ranging_table_find(const struct ranging_table *t, uint16_t peer_id);
/** True if the entry holds a distance measured less than stale_after_us before now_us. */
extern bool ranging_table_is_fresh(const struct ranging_table *t, const struct ranging_peer *p, uint32_t now_us);
/** Copy the fresh distances into out (at most max); returns how many. */
extern unsigned ranging_table_fresh_distances(const struct ranging_table *t, uint32_t now_us, float *out, unsigned max);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_TABLE_H */
