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

#include <string.h>

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
  return wall_detector_peers_slot_used(peers, slot) &&
         wall_detector_is_fresh(peers->newest_stamp_us[slot], now_us, age_limit_us) &&
         peers->newest_m[slot] < ranging_max_m;
}

/** Slot of a peer in the table, -1 when it is not. */
static int own_slot(const struct wall_detector_peers *peers, uint16_t peer_id)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (wall_detector_peers_slot_used(peers, i) && peers->id[i] == peer_id) {
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
static int new_slot(const struct wall_detector_peers *peers, uint32_t now_us, int64_t age_limit_us,
                    float ranging_max_m)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (!wall_detector_peers_slot_used(peers, i)) {
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
  const int own = own_slot(peers, peer_id);
  if (own < 0 && distance_m >= ranging_max_m) {
    return -1;   /* out of range and not in the table: nothing to remember, no slot taken */
  }
  const int slot = own >= 0 ? own : new_slot(peers, stamp_us, age_limit_us, ranging_max_m);
  struct wall_detector_peer *peer = &peers->slot[slot];
  *is_new = own < 0;
  if (*is_new) {
    /* a new peer in this slot: no distances */
    *peer = (struct wall_detector_peer) { .prior_odds = NAN };
    peers->used_slots |= 1u << slot;
    peers->id[slot] = peer_id;
  } else if (distance_m >= ranging_max_m && fresh_in_range(peers, slot, stamp_us, age_limit_us, ranging_max_m)) {
    return slot;
  }
  peers->candidates_for_us = 0;
  if (peer->count > 0) {
    peer->latest = (uint8_t)((peer->latest + 1) % WALL_DETECTOR_PEER_HISTORY);
  }
  if (peer->count < WALL_DETECTOR_PEER_HISTORY) {
    peer->count++;
  }
  peer->distance_m[peer->latest] = distance_m;
  peer->stamp_us[peer->latest] = stamp_us;
  peer->median_of = 0;
  peer->fresh_for_us = 0;
  peers->newest_m[slot] = distance_m;
  peers->newest_stamp_us[slot] = stamp_us;
  return slot;
}

/** A key that orders distances as a stable sort does: by value (a float's bits as an integer, negatives reversed;
 * -0 as +0, equal to it), then by place in the history. Distances are never NaN (wall_detector_filter_ranging). */
static uint64_t stable_order_key(float distance_m, int index)
{
  const float value = distance_m + 0.f;  // -0 + +0 = +0 (round to nearest): -0 and +0 get the same key
  uint32_t bits;
  memcpy(&bits, &value, sizeof(bits));
  /* a negative value (sign bit set, sign_mask all ones) has all its bits flipped, a positive one its sign bit set */
  const uint32_t sign_mask = (uint32_t)((int32_t)bits >> 31);
  const uint32_t ordered = bits ^ (sign_mask | 0x80000000u);
  return ((uint64_t)ordered << 3) | (uint64_t)index;
}

_Static_assert(WALL_DETECTOR_PEER_HISTORY <= 8, "stable_order_key keeps a distance's index in 3 bits");

/**
 * The median of the distances of a peer marked in `of` (bit i: distance_m[i]; the mean of the middle two), as a
 * stable sort finds it (-0 and +0 too). The marked distances' keys (stable_order_key: all distinct, so any sort
 * puts them in the stable sort's order) and the largest key for each unmarked slot are sorted by an odd-even
 * transposition network (N rounds of compare-exchanges between neighbours sort N keys), which has no branches to
 * mispredict; the middle keys name the middle distances.
 */
static float median_distance(const struct wall_detector_peer *peer, uint8_t of)
{
  enum { N = WALL_DETECTOR_PEER_HISTORY };
  uint64_t key[N];
  int n = 0;
#pragma GCC unroll 8
  for (int i = 0; i < N; i++) {
    const bool marked = (of >> i) & 1u;
    key[i] = marked ? stable_order_key(peer->distance_m[i], i) : UINT64_MAX;
    n += marked;
  }
#pragma GCC unroll 8
  for (int round = 0; round < N; round++) {
#pragma GCC unroll 8
    for (int i = round % 2; i + 1 < N; i += 2) {
      const uint64_t low = key[i] < key[i + 1] ? key[i] : key[i + 1];
      const uint64_t high = key[i] < key[i + 1] ? key[i + 1] : key[i];
      key[i] = low;
      key[i + 1] = high;
    }
  }
  const float low_m = peer->distance_m[key[(n - 1) / 2] & 7u];
  const float high_m = peer->distance_m[key[n / 2] & 7u];
  return 0.5f * (low_m + high_m);
}

/** Time from an age to the next age `flip` (modulo 2^32) [us]; 2^32 - 1 when the age is at it (it comes back
 * 2^32 us later). */
static uint32_t time_to_age(uint32_t age_us, uint32_t flip_us)
{
  const uint32_t wait_us = flip_us - age_us;
  return wait_us == 0 ? UINT32_MAX : wait_us;
}

/**
 * The fresh distances of a peer at now_us (bit i: distance_m[i]), from the cache while it holds. A distance's
 * freshness (int32_t)(now_us - stamp_us) <= age_limit_us changes only when its age, now_us - stamp_us modulo
 * 2^32, reaches age_limit_us + 1 (it goes stale) or 2^31 (the int32 wraps), so the set holds until the first of
 * these; a clock going back breaks the cache too ((uint32_t)(now_us - fresh_at_us) is then large).
 */
static uint8_t fresh_distances(struct wall_detector_peer *peer, uint32_t now_us, int64_t age_limit_us)
{
  if ((uint32_t)(now_us - peer->fresh_at_us) >= peer->fresh_for_us) {
    const uint32_t stale_age_us = (uint32_t)(age_limit_us + 1);
    const uint32_t wrap_age_us = UINT32_C(1) << 31;
    uint8_t fresh = 0;
    uint32_t hold_us = UINT32_MAX;
    for (int i = 0; i < peer->count; i++) {
      const uint32_t age_us = now_us - peer->stamp_us[i];
      fresh |= (uint8_t)(wall_detector_is_fresh(peer->stamp_us[i], now_us, age_limit_us) << i);
      const uint32_t flip_us = time_to_age(age_us, stale_age_us) < time_to_age(age_us, wrap_age_us) ?
                               time_to_age(age_us, stale_age_us) : time_to_age(age_us, wrap_age_us);
      hold_us = flip_us < hold_us ? flip_us : hold_us;
    }
    peer->fresh = fresh;
    peer->fresh_at_us = now_us;
    peer->fresh_for_us = hold_us;
  }
  return peer->fresh;
}

/**
 * The distance an echo of the peer in a used `slot` is judged against: the median of its fresh distances
 * (cached; what was derived from the median is kept while its value is the same).
 * @param[out] hold_us how long from now_us the peer's fresh distances stay the same [us]
 * @return false when the peer cannot explain an echo now (its newest distance stale or out of range, the median
 *         out of range)
 */
static bool median_distance_now(struct wall_detector_peers *peers, int slot, uint32_t now_us, int64_t age_limit_us,
                                float ranging_max_m, float *distance_m, uint32_t *hold_us)
{
  struct wall_detector_peer *peer = &peers->slot[slot];
  const uint8_t fresh = fresh_distances(peer, now_us, age_limit_us);
  *hold_us = peer->fresh_for_us - (now_us - peer->fresh_at_us);  // >= 1: fresh_distances found them valid now
  /* the newest distance (newest_m, newest_stamp_us) is distance_m[latest] */
  if (!((fresh & (1u << peer->latest)) && peers->newest_m[slot] < ranging_max_m)) {
    return false;
  }
  if (fresh != peer->median_of) {
    peer->median_of = fresh;
    const float median_m = median_distance(peer, fresh);
    if (median_m != peer->median_m) {
      peer->median_m = median_m;
      peer->prior_odds = NAN;
    }
  }
  *distance_m = peer->median_m;
  return *distance_m < ranging_max_m;
}

/** The prior odds rho of the peer in `slot` on one sonar at its median distance (cached). */
static double prior_odds(struct wall_detector_peers *peers, int slot, const struct wall_detector_model *model)
{
  struct wall_detector_peer *peer = &peers->slot[slot];
  if (isnan(peer->prior_odds)) {
    const double pi = wall_detector_peer_prior(model, peer->median_m);
    peer->prior_odds = pi / (1.0 - WALL_DETECTOR_SONAR_NB * pi);
  }
  return peer->prior_odds;
}

const struct wall_detector_candidates *wall_detector_peers_candidates(struct wall_detector_peers *peers,
    uint32_t now_us, int64_t age_limit_us, const struct wall_detector_model *model)
{
  struct wall_detector_candidates *candidates = &peers->candidates;
  if ((uint32_t)(now_us - peers->candidates_at_us) < peers->candidates_for_us) {
    return candidates;  // nothing they depend on changed since they were listed
  }
  /* the list holds until a distance is recorded or a peer's fresh distances change (the first of these) */
  unsigned nb = 0, slot_set = 0;
  uint32_t hold_us = UINT32_MAX;
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    float distance_m;
    uint32_t peer_hold_us;
    if (!wall_detector_peers_slot_used(peers, k)) {
      continue;
    }
    const bool candidate = median_distance_now(peers, k, now_us, age_limit_us, model->ranging_max_m, &distance_m,
                           &peer_hold_us);
    hold_us = peer_hold_us < hold_us ? peer_hold_us : hold_us;
    if (candidate) {
      candidates->slot[nb] = k;
      candidates->distance_m[nb] = distance_m;
      candidates->newest_m[nb] = peers->newest_m[k];
      candidates->prior_odds[nb] = prior_odds(peers, k, model);
      slot_set |= 1u << k;
      nb++;
    }
  }
  candidates->nb = nb;
  candidates->slot_set = slot_set;
  peers->candidates_listing++;
  peers->candidates_at_us = now_us;
  peers->candidates_for_us = hold_us;
  return candidates;
}

void wall_detector_peers_timeout_changed(struct wall_detector_peers *peers)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    peers->slot[i].fresh_for_us = 0;
  }
  peers->candidates_for_us = 0;
}

void wall_detector_peers_model_changed(struct wall_detector_peers *peers)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    peers->slot[i].prior_odds = NAN;
  }
  peers->candidates_for_us = 0;
}
