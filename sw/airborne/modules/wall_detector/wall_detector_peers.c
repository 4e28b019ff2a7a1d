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

int64_t wall_detector_fresh_age_limit_us(float timeout_s)
{
  if ((float)INT32_MAX * 1e-6f <= timeout_s) {
    return INT32_MAX;
  }
  if (!((float)INT32_MIN * 1e-6f <= timeout_s)) {
    return (int64_t)INT32_MIN - 1;
  }
  /* from the nearest microsecond, step to the boundary (a step or two: ages near it are exact in a float) */
  const double guess_us = timeout_s * 1e6;
  int32_t age_us = guess_us < INT32_MIN ? INT32_MIN : (guess_us > INT32_MAX - 1.0 ? INT32_MAX - 1 : (int32_t)guess_us);
  while (!((float)age_us * 1e-6f <= timeout_s)) {
    age_us--;
  }
  while ((float)(age_us + 1) * 1e-6f <= timeout_s) {
    age_us++;
  }
  return age_us;
}

/** True for a peer in `slot` heard within the timeout whose newest distance is within the ranging range. */
static bool fresh_in_range(const struct wall_detector_peers *peers, int slot, uint32_t now_us, int64_t age_limit_us,
                           float ranging_max_m)
{
  return peers->used[slot] && wall_detector_is_fresh(peers->newest_stamp_us[slot], now_us, age_limit_us) &&
         peers->newest_m[slot] < ranging_max_m;
}

/**
 * Slot of a peer: its own, else a free one, else the one heard from longest ago among the peers that cannot
 * explain an echo now (stale or out of range), else the one heard from longest ago. In a dense swarm the peers
 * beyond the ranging range, reported at the maximum, must not push the near ones out of the table.
 */
static int peer_slot(const struct wall_detector_peers *peers, uint16_t peer_id, uint32_t now_us,
                     int64_t age_limit_us, float ranging_max_m)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (peers->used[i] && peers->id[i] == peer_id) {
      return i;
    }
  }
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (!peers->used[i]) {
      return i;
    }
  }
  int stalest = 0;
  bool stalest_candidate = true;
  float stalest_age_s = -INFINITY;
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    const bool candidate = fresh_in_range(peers, i, now_us, age_limit_us, ranging_max_m);
    const float age_s = wall_detector_elapsed_s(now_us, peers->newest_stamp_us[i]);
    if ((stalest_candidate && !candidate) || (candidate == stalest_candidate && age_s > stalest_age_s)) {
      stalest = i;
      stalest_candidate = candidate;
      stalest_age_s = age_s;
    }
  }
  return stalest;
}

int wall_detector_peers_record(struct wall_detector_peers *peers, uint16_t peer_id, float distance_m,
                               uint32_t stamp_us, float ranging_max_m, int64_t age_limit_us, bool *is_new)
{
  const int slot = peer_slot(peers, peer_id, stamp_us, age_limit_us, ranging_max_m);
  const bool known = peers->used[slot] && peers->id[slot] == peer_id;
  if (!known && distance_m >= ranging_max_m) {
    return -1;   /* out of range and not in the table: nothing to remember, no slot taken */
  }
  struct wall_detector_peer *peer = &peers->slot[slot];
  *is_new = !known;
  if (*is_new) {
    /* a new peer in this slot: no distances */
    *peer = (struct wall_detector_peer) { .clamped_llr = NAN, .prior_odds = NAN };
    peers->used[slot] = true;
    peers->id[slot] = peer_id;
  } else if (distance_m >= ranging_max_m && fresh_in_range(peers, slot, stamp_us, age_limit_us, ranging_max_m)) {
    return slot;
  }
  if (peer->count > 0) {
    peer->latest = (uint8_t)((peer->latest + 1) % WALL_DETECTOR_PEER_HISTORY);
  }
  if (peer->count < WALL_DETECTOR_PEER_HISTORY) {
    peer->count++;
  }
  peer->distance_m[peer->latest] = distance_m;
  peer->stamp_us[peer->latest] = stamp_us;
  peer->median_of = 0;
  peers->newest_m[slot] = distance_m;
  peers->newest_stamp_us[slot] = stamp_us;
  return slot;
}

/** The median of the distances of a peer marked in `of` (bit i: distance_m[i]; the mean of the middle two). */
static float median_distance(const struct wall_detector_peer *peer, uint8_t of)
{
  float d[WALL_DETECTOR_PEER_HISTORY];
  int n = 0;
  for (int i = 0; i < peer->count; i++) {
    if (of & (1u << i)) {
      d[n++] = peer->distance_m[i];
    }
  }
  /* insertion sort of at most WALL_DETECTOR_PEER_HISTORY values */
  for (int i = 1; i < n; i++) {
    const float next = d[i];
    int j = i;
    for (; j > 0 && d[j - 1] > next; j--) {
      d[j] = d[j - 1];
    }
    d[j] = next;
  }
  return 0.5f * (d[(n - 1) / 2] + d[n / 2]);
}

bool wall_detector_peers_distance(struct wall_detector_peers *peers, int slot, uint32_t now_us,
                                  int64_t age_limit_us, float ranging_max_m, float *distance_m)
{
  if (!fresh_in_range(peers, slot, now_us, age_limit_us, ranging_max_m)) {
    return false;
  }
  struct wall_detector_peer *peer = &peers->slot[slot];
  uint8_t fresh = 0;
  for (int i = 0; i < peer->count; i++) {
    fresh |= (uint8_t)(wall_detector_is_fresh(peer->stamp_us[i], now_us, age_limit_us) << i);
  }
  if (fresh != peer->median_of) {
    peer->median_of = fresh;
    peer->median_m = median_distance(peer, fresh);
    peer->prior_odds = NAN;
    peer->clamped_llr = NAN;
  }
  *distance_m = peer->median_m;
  return *distance_m < ranging_max_m;
}

double wall_detector_peers_prior_odds(struct wall_detector_peers *peers, int slot,
                                      const struct wall_detector_model *model)
{
  struct wall_detector_peer *peer = &peers->slot[slot];
  if (isnan(peer->prior_odds)) {
    const double pi = wall_detector_peer_prior(model, peer->median_m);
    peer->prior_odds = pi / (1.0 - WALL_DETECTOR_SONAR_NB * pi);
  }
  return peer->prior_odds;
}

float wall_detector_peers_clamped_llr(struct wall_detector_peers *peers, int slot,
                                      const struct wall_detector_model_terms *terms)
{
  struct wall_detector_peer *peer = &peers->slot[slot];
  if (isnan(peer->clamped_llr)) {
    peer->clamped_llr = wall_detector_reading_llr(terms, terms->model.sonar_min_m, peer->median_m);
  }
  return peer->clamped_llr;
}

void wall_detector_peers_model_changed(struct wall_detector_peers *peers)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    peers->slot[i].prior_odds = NAN;
    peers->slot[i].clamped_llr = NAN;
  }
}
