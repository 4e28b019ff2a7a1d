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
 * @file modules/wall_detector/wall_detector_peers.c
 * The wall detector's table of ranged peers (see wall_detector_peers.h).
 */

#include "modules/wall_detector/wall_detector_peers.h"
#include "modules/wall_detector/wall_detector_pose.h"

bool wall_detector_is_fresh(uint32_t then_us, uint32_t now_us, float timeout_s)
{
  return wall_detector_elapsed_s(now_us, then_us) <= timeout_s;
}

/** True for a peer whose newest distance is fresh and within the ranging range. */
static bool fresh_in_range(const struct wall_detector_peer *peer, uint32_t now_us, float timeout_s,
                           float ranging_max_m)
{
  return peer->used && wall_detector_is_fresh(peer->stamp_us[peer->latest], now_us, timeout_s) &&
         peer->distance_m[peer->latest] < ranging_max_m;
}

/** Slot of a peer in the table, -1 when it is not. */
static int own_slot(const struct wall_detector_peers *peers, uint16_t peer_id)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (peers->slot[i].used && peers->slot[i].id == peer_id) {
      return i;
    }
  }
  return -1;
}

/**
 * Slot for a new peer: a free one, else the one heard from longest ago among the peers that cannot explain an
 * echo now (stale or out of range), else the one heard from longest ago. In a dense swarm the peers beyond the
 * ranging range, reported at the maximum, must not push the near ones out of the table.
 */
static int new_slot(const struct wall_detector_peers *peers, uint32_t now_us, float timeout_s, float ranging_max_m)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (!peers->slot[i].used) {
      return i;
    }
  }
  int stalest = 0;
  bool stalest_candidate = true;
  float stalest_age_s = -INFINITY;
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    const struct wall_detector_peer *peer = &peers->slot[i];
    const bool candidate = fresh_in_range(peer, now_us, timeout_s, ranging_max_m);
    const float age_s = wall_detector_elapsed_s(now_us, peer->stamp_us[peer->latest]);
    if ((stalest_candidate && !candidate) || (candidate == stalest_candidate && age_s > stalest_age_s)) {
      stalest = i;
      stalest_candidate = candidate;
      stalest_age_s = age_s;
    }
  }
  return stalest;
}

int wall_detector_peers_record(struct wall_detector_peers *peers, uint16_t peer_id, float distance_m,
                               uint32_t stamp_us, float ranging_max_m, float timeout_s, bool *is_new)
{
  const int own = own_slot(peers, peer_id);
  if (own < 0 && distance_m >= ranging_max_m) {
    return -1;   // out of range and not in the table: nothing to remember, no slot taken
  }
  const int slot = own >= 0 ? own : new_slot(peers, stamp_us, timeout_s, ranging_max_m);
  struct wall_detector_peer *peer = &peers->slot[slot];
  *is_new = own < 0;
  if (*is_new) {
    *peer = (struct wall_detector_peer) { .used = true, .id = peer_id };  // no distances yet
  } else if (distance_m >= ranging_max_m && fresh_in_range(peer, stamp_us, timeout_s, ranging_max_m)) {
    return slot;   // the error's tail reaches the maximum: the fresh distance in range stands
  }
  if (peer->count > 0) {
    peer->latest = (uint8_t)((peer->latest + 1) % WALL_DETECTOR_PEER_HISTORY);
  }
  if (peer->count < WALL_DETECTOR_PEER_HISTORY) {
    peer->count++;
  }
  peer->distance_m[peer->latest] = distance_m;
  peer->stamp_us[peer->latest] = stamp_us;
  return slot;
}

/** The median of a peer's fresh distances (the mean of the middle two for an even number); none when its newest
 * distance is stale. */
static bool fresh_median(const struct wall_detector_peer *peer, uint32_t now_us, float timeout_s, float *median_m)
{
  /* the fresh distances, sorted by insertion */
  float sorted_m[WALL_DETECTOR_PEER_HISTORY];
  int n = 0;
  for (int i = 0; i < peer->count; i++) {
    if (wall_detector_is_fresh(peer->stamp_us[i], now_us, timeout_s)) {
      int j = n++;
      for (; j > 0 && sorted_m[j - 1] > peer->distance_m[i]; j--) {
        sorted_m[j] = sorted_m[j - 1];
      }
      sorted_m[j] = peer->distance_m[i];
    }
  }
  if (n == 0 || !wall_detector_is_fresh(peer->stamp_us[peer->latest], now_us, timeout_s)) {
    return false;
  }
  *median_m = 0.5f * (sorted_m[(n - 1) / 2] + sorted_m[n / 2]);
  return true;
}

void wall_detector_peers_candidates(const struct wall_detector_peers *peers, uint32_t now_us, float timeout_s,
                                    const struct wall_detector_model *model,
                                    struct wall_detector_candidates *candidates)
{
  candidates->nb = 0;
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    const struct wall_detector_peer *peer = &peers->slot[k];
    const float newest_m = peer->distance_m[peer->latest];
    float median_m;
    if (!peer->used || !(newest_m < model->ranging_max_m) || !fresh_median(peer, now_us, timeout_s, &median_m) ||
        !(median_m < model->ranging_max_m)) {
      continue;
    }
    const double pi = wall_detector_peer_prior(model, median_m);
    const unsigned i = candidates->nb++;
    candidates->slot[i] = k;
    candidates->distance_m[i] = median_m;
    candidates->newest_m[i] = newest_m;
    candidates->prior_odds[i] = pi / (1.0 - WALL_DETECTOR_SONAR_NB * pi);
  }
}
