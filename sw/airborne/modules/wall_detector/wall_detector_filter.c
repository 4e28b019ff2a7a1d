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
 * @file modules/wall_detector/wall_detector_filter.c
 * Sequence filter of the wall detector (see wall_detector_filter.h for the law).
 */

#include "modules/wall_detector/wall_detector_filter.h"

#include <math.h>
#include <string.h>

/** Signed time from `then_us` to `now_us` [s]; wrap-safe for uint32 microsecond clocks. */
static float elapsed_s(uint32_t now_us, uint32_t then_us)
{
  return (float)(int32_t)(now_us - then_us) * 1e-6f;
}

static float clampf(float x, float bound)
{
  return x > bound ? bound : (x < -bound ? -bound : x);
}

void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params)
{
  memset(filter, 0, sizeof(*filter));
  filter->params = *params;
}

/** Slot of a peer: its own, else a free one, else the one heard from longest ago. */
static int peer_slot(const struct wall_detector_filter *filter, uint16_t peer_id, uint32_t now_us)
{
  int free_slot = -1;
  int stalest = 0;
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    const struct wall_detector_peer *p = &filter->peers[i];
    if (p->used && p->id == peer_id) {
      return i;
    }
    if (!p->used && free_slot < 0) {
      free_slot = i;
    }
    const struct wall_detector_peer *q = &filter->peers[stalest];
    if (elapsed_s(now_us, p->stamp_us[p->latest]) > elapsed_s(now_us, q->stamp_us[q->latest])) {
      stalest = i;
    }
  }
  return free_slot >= 0 ? free_slot : stalest;
}

/** True for a peer heard within the timeout whose newest distance is within the ranging range. */
static bool peer_fresh_in_range(const struct wall_detector_params *params, const struct wall_detector_peer *peer,
                                uint32_t now_us)
{
  return peer->used && elapsed_s(now_us, peer->stamp_us[peer->latest]) <= params->peer_timeout_s &&
         peer->distance_m[peer->latest] < params->model.ranging_max_m;
}

int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                 uint32_t stamp_us)
{
  if (!isfinite(distance_m) || distance_m < 0.f) {
    return -1;
  }
  const int slot = peer_slot(filter, peer_id, stamp_us);
  struct wall_detector_peer *peer = &filter->peers[slot];
  if (!peer->used || peer->id != peer_id) {
    /* a new peer in this slot: no distances, its evidence starts from nothing */
    *peer = (struct wall_detector_peer) { .used = true, .id = peer_id };
    for (int s = 0; s < WALL_DETECTOR_SONAR_NB; s++) {
      filter->sonars[s].evidence[slot] = 0.f;
    }
  } else if (distance_m >= filter->params.model.ranging_max_m && peer_fresh_in_range(&filter->params, peer, stamp_us)) {
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
  return slot;
}

/**
 * The distance an echo of this peer is judged against: the median of its fresh distances (the mean of two).
 * @return false when the peer cannot explain an echo now (unused, not heard within the timeout, out of range)
 */
static bool peer_distance(const struct wall_detector_params *params, const struct wall_detector_peer *peer,
                          uint32_t now_us, float *distance_m)
{
  if (!peer_fresh_in_range(params, peer, now_us)) {
    return false;
  }
  float d[WALL_DETECTOR_PEER_HISTORY];
  int n = 0;
  for (int i = 0; i < peer->count; i++) {
    if (elapsed_s(now_us, peer->stamp_us[i]) <= params->peer_timeout_s) {
      d[n++] = peer->distance_m[i];
    }
  }
  if (n == 3) {
    *distance_m = fmaxf(fminf(d[0], d[1]), fminf(fmaxf(d[0], d[1]), d[2]));
  } else {
    *distance_m = n == 2 ? 0.5f * (d[0] + d[1]) : d[0];
  }
  return *distance_m < params->model.ranging_max_m;
}

float wall_detector_filter_discount(const struct wall_detector_params *params,
                                    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose,
                                    uint32_t now_us)
{
  if (!sonar->started) {
    return 0.f;
  }
  const float dt_s = fmaxf(elapsed_s(now_us, sonar->stamp_us), 0.f);
  const float ds_m = hypotf(pose->x_m - sonar->pose.x_m, pose->y_m - sonar->pose.y_m);
  const float dpsi_rad = fabsf(remainderf(pose->yaw_rad - sonar->pose.yaw_rad, 2.f * (float)M_PI));
  return expf(-dt_s / params->evidence_tau_s - ds_m / params->move_scale_m - dpsi_rad / params->turn_scale_rad);
}

/** The best claim of the other sonars on peer k: max(0, their largest evidence for it). */
static float claimed_elsewhere(const struct wall_detector_filter *filter, int sonar, int k)
{
  float claim = 0.f;
  for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
    if (o != sonar) {
      claim = fmaxf(claim, filter->sonars[o].evidence[k]);
    }
  }
  return claim;
}

int wall_detector_filter_sonar(struct wall_detector_filter *filter, int sonar, float range_m,
                               const struct wall_detector_pose *pose, uint32_t now_us,
                               struct wall_detector_decision *decision)
{
  if (sonar < 0 || sonar >= WALL_DETECTOR_SONAR_NB || !isfinite(range_m) || range_m < 0.f) {
    return -1;
  }
  const struct wall_detector_params *p = &filter->params;
  struct wall_detector_sonar *s = &filter->sonars[sonar];
  const float lambda = wall_detector_filter_discount(p, s, pose, now_us);
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    s->evidence[k] *= lambda;
  }
  s->started = true;
  s->stamp_us = now_us;
  s->pose = *pose;

  decision->repulsion_m = range_m;
  decision->attraction_m = -1.f;
  if (!wall_detector_is_echo(&p->model, range_m)) {
    /* nothing hit: no evidence either way, and the next echo is compared with the last one */
    decision->target_class = WALL_DETECTOR_NO_ECHO;
    decision->baseline_class = WALL_DETECTOR_NO_ECHO;
    decision->log_odds = 0.f;
    decision->confidence = 1.f;
    return 0;
  }
  const bool jumped = fabsf(range_m - s->range_m) > p->jump_m;
  s->range_m = range_m;

  /* update every peer (restarting it after a jump unless it explains both targets) */
  int in_range[WALL_DETECTOR_MAX_PEERS];
  float distance_m[WALL_DETECTOR_MAX_PEERS];
  float latest_m[WALL_DETECTOR_MAX_PEERS];  // the baseline judges by the newest distance, as the original
  unsigned peer_nb = 0;
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    const struct wall_detector_peer *peer = &filter->peers[k];
    float d_m = 0.f;
    const bool candidate = peer_distance(p, peer, now_us, &d_m);
    const float llr = candidate ? wall_detector_reading_llr(&p->model, range_m, d_m) : 0.f;
    /* after a jump, keep a peer's evidence only if it favoured the peer and the new reading is more likely the
     * peer's echo or cross-talk than an outlier: (1 - eps - chi) r_echo + chi r_ct > eps <=> llr > log(2 eps) */
    if (jumped && !(candidate && s->evidence[k] > 0.f && llr > logf(2.f * p->model.outlier_prob))) {
      s->evidence[k] = 0.f;  // another target: this peer's evidence starts anew
    }
    if (candidate) {
      s->evidence[k] = clampf(s->evidence[k] + llr, p->evidence_max);
      in_range[peer_nb] = k;
      distance_m[peer_nb] = d_m;
      latest_m[peer_nb++] = peer->distance_m[peer->latest];
    }
  }
  float log_odds = -p->evidence_max;
  if (peer_nb > 0) {
    /* a peer is on one sonar at most, unless close enough for two boresights to hit it (file comment): the
     * other sonars' evidence for it competes */
    const float touching_m = (float)M_SQRT2 * p->model.copter_offset_m + 2.f * p->model.ranging_sigma_m;
    float shared[WALL_DETECTOR_MAX_PEERS];
    float largest = -INFINITY;
    for (unsigned i = 0; i < peer_nb; i++) {
      const bool exclusive = distance_m[i] > touching_m;
      shared[i] = s->evidence[in_range[i]] - (exclusive ? claimed_elsewhere(filter, sonar, in_range[i]) : 0.f);
      largest = fmaxf(largest, shared[i]);
    }
    float sum = 0.f;
    for (unsigned i = 0; i < peer_nb; i++) {
      sum += expf(shared[i] - largest);
    }
    log_odds = largest + logf(sum / (float)peer_nb);
  }

  decision->log_odds = log_odds;
  decision->confidence = 1.f / (1.f + expf(-fabsf(log_odds)));
  if (log_odds <= -p->wall_threshold) {
    decision->target_class = WALL_DETECTOR_WALL;
  } else if (log_odds >= p->copter_threshold) {
    decision->target_class = WALL_DETECTOR_COPTER;
    decision->attraction_m = range_m;
  } else {
    decision->target_class = WALL_DETECTOR_UNKNOWN;
  }
  decision->baseline_class = wall_detector_baseline_class(&p->model, range_m, latest_m, peer_nb,
                             p->baseline_eps_m);
  return 0;
}

int wall_detector_sonar_index(float heading_rad)
{
  if (!isfinite(heading_rad)) {
    return -1;
  }
  /* front 0, right pi/2, back pi, left -pi/2: quarter turns clockwise (seen from above) from the front */
  const long quarter = lroundf(remainderf(heading_rad, 2.f * (float)M_PI) / (float)(M_PI / 2.0));
  return (int)(((quarter % WALL_DETECTOR_SONAR_NB) + WALL_DETECTOR_SONAR_NB) % WALL_DETECTOR_SONAR_NB);
}
