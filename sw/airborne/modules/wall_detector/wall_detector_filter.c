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
 * The distance an echo of this peer is judged against: the median of its fresh distances (with an even number,
 * the mean of the middle two).
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
  /* the median (insertion sort of at most WALL_DETECTOR_PEER_HISTORY values; the mean of the middle two) */
  for (int i = 1; i < n; i++) {
    for (int j = i; j > 0 && d[j - 1] > d[j]; j--) {
      const float swap = d[j];
      d[j] = d[j - 1];
      d[j - 1] = swap;
    }
  }
  *distance_m = 0.5f * (d[(n - 1) / 2] + d[n / 2]);
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

/** True when one of two readings is best explained as peer_distance_m's echo and the other as its cross-talk. */
static bool echo_and_crosstalk(const struct wall_detector_model *model, float first_m, float second_m,
                               float peer_distance_m)
{
  const enum wall_detector_part a = wall_detector_reading_part(model, first_m, peer_distance_m);
  const enum wall_detector_part b = wall_detector_reading_part(model, second_m, peer_distance_m);
  return (a == WALL_DETECTOR_PART_ECHO && b == WALL_DETECTOR_PART_CROSSTALK) ||
         (a == WALL_DETECTOR_PART_CROSSTALK && b == WALL_DETECTOR_PART_ECHO);
}

/** Unit vector (east, north) of sonar `sonar`'s boresight: headings clockwise from the nose, a quarter turn apart. */
static void boresight(const struct wall_detector_pose *pose, int sonar, float *east, float *north)
{
  const float bearing_rad = pose->yaw_rad + (float)sonar * (float)(M_PI / 2.0);
  *east = sinf(bearing_rad);
  *north = cosf(bearing_rad);
}

/** Position of the copter along sonar `sonar`'s boresight and across it (to its right) [m]. */
static void boresight_position(const struct wall_detector_pose *pose, int sonar, float *along_m, float *lateral_m)
{
  float east, north;
  boresight(pose, sonar, &east, &north);
  *along_m = pose->x_m * east + pose->y_m * north;
  *lateral_m = pose->x_m * north - pose->y_m * east;
}

bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep)
{
  if (!state->wall_known) {
    return false;
  }
  float along_m, lateral_m, last_along_m, last_lateral_m;  // now and at the last remembered reading
  boresight_position(pose, sonar, &along_m, &lateral_m);
  boresight_position(&state->wall_pose, sonar, &last_along_m, &last_lateral_m);
  const float dt_s = fmaxf(elapsed_s(now_us, state->wall_stamp_us), 0.f);
  const float dpsi_rad = fabsf(remainderf(pose->yaw_rad - state->wall_pose.yaw_rad, 2.f * (float)M_PI));
  /* a wall is a line: reading + position along the boresight = a + slope x position across it (least squares
   * over the remembered readings, the slope shrunk toward 0, square to the beam, while the sideways spread is
   * small); a static wall reads closer by the own advance along the boresight */
  const float slope = state->wall_cov_m2 / (state->wall_lateral_var_m2 +
                      WALL_DETECTOR_TRACK_SPREAD * WALL_DETECTOR_TRACK_SPREAD);
  *predicted_m = state->wall_along_m + slope * (lateral_m - state->wall_lateral_m) - along_m;
  *keep = (1.f - params->model.outlier_prob) * expf(-dt_s / params->evidence_tau_s -
          fabsf(lateral_m - last_lateral_m) / params->move_scale_m - dpsi_rad / params->turn_scale_rad);
  return true;
}

/**
 * Average a reading judged a wall into the sonar's remembered wall (its position along the boresight). A reading
 * off the remembered wall by more than the gate starts a new one only once the old one is half forgotten
 * (keep below half its most): a nearer echo in front of a wall still in view is rather a body between (whose
 * peer's ranging may lag) than another wall.
 */
static void remember_wall(const struct wall_detector_params *params, int sonar, struct wall_detector_sonar *state,
                          float range_m, const struct wall_detector_pose *pose, uint32_t now_us, float predicted_m,
                          float keep)
{
  if (!state->wall_known) {
    state->wall_known = true;
    state->wall_readings = 0;
  } else if (fabsf(range_m - predicted_m) > WALL_DETECTOR_TRACK_GATE * params->model.track_sigma_m) {
    if (keep > 0.5f * (1.f - params->model.outlier_prob)) {
      return;
    }
    state->wall_readings = 0;
  }
  if (state->wall_readings < WALL_DETECTOR_TRACK_READINGS) {
    state->wall_readings++;
  }
  /* means, variance and covariance of the readings so far, then running ones over the last
   * WALL_DETECTOR_TRACK_READINGS (weight w = 1 / n: m += w d, C = (1 - w) (C + w d_l d)) */
  float along_m, lateral_m;
  boresight_position(pose, sonar, &along_m, &lateral_m);
  const float w = 1.f / state->wall_readings;
  const float d_wall_m = range_m + along_m - state->wall_along_m;
  const float d_lateral_m = lateral_m - state->wall_lateral_m;
  state->wall_along_m += w * d_wall_m;
  state->wall_lateral_m += w * d_lateral_m;
  state->wall_lateral_var_m2 = (1.f - w) * (state->wall_lateral_var_m2 + w * d_lateral_m * d_lateral_m);
  state->wall_cov_m2 = (1.f - w) * (state->wall_cov_m2 + w * d_lateral_m * d_wall_m);
  state->wall_pose = *pose;
  state->wall_stamp_us = now_us;
}

/**
 * Posterior log-odds that sonar `sonar` sees a copter (file comment: the joint assignment). weight[o][0] is a
 * wall's weight (1) and weight[o][i + 1] that of in-range peer i on sonar o, each row scaled by a constant: the
 * odds are the same for the other sonars' rows (every term has one factor of each) and corrected for this one.
 */
static float assignment_log_odds(double weight[WALL_DETECTOR_SONAR_NB][WALL_DETECTOR_MAX_PEERS + 1],
                                 double own_scale, int sonar, unsigned peer_nb)
{
  int other[WALL_DETECTOR_SONAR_NB - 1];
  for (int o = 0, n = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
    if (o != sonar) {
      other[n++] = o;
    }
  }
  const double *w0 = weight[other[0]], *w1 = weight[other[1]], *w2 = weight[other[2]];
  double copter = 0.0, wall = 0.0;
  /* index 0 is a wall (any number of sonars), 1..peer_nb the peers (one sonar each) */
  for (unsigned a = 0; a <= peer_nb; a++) {
    for (unsigned b = 0; b <= peer_nb; b++) {
      if (b != 0 && b == a) {
        continue;
      }
      for (unsigned c = 0; c <= peer_nb; c++) {
        if (c != 0 && (c == a || c == b)) {
          continue;
        }
        const double others = w0[a] * w1[b] * w2[c];
        wall += others;
        for (unsigned k = 1; k <= peer_nb; k++) {
          if (k != a && k != b && k != c) {
            copter += others * weight[sonar][k];
          }
        }
      }
    }
  }
  return (float)(log(copter) + own_scale - log(wall));
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
  const float previous_m = s->range_m;
  s->range_m = range_m;

  /* what the remembered wall says (the same for every peer) */
  float track_llr = 0.f, predicted_m = 0.f, keep = 0.f;
  if (wall_detector_filter_wall_prediction(p, sonar, s, pose, now_us, &predicted_m, &keep)) {
    track_llr = wall_detector_track_llr(&p->model, range_m, predicted_m, keep);
    if (range_m > predicted_m + WALL_DETECTOR_TRACK_GATE * p->model.track_sigma_m) {
      s->wall_known = false;  // an echo from beyond it: it was no wall
    }
  }

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
    /* after a jump, keep a peer's evidence only if it favoured the peer and the jump went between that peer's
     * echo and its cross-talk (a facing copter's readings alternate between the two) */
    if (jumped && !(candidate && s->evidence[k] > 0.f && echo_and_crosstalk(&p->model, previous_m, range_m, d_m))) {
      s->evidence[k] = 0.f;  // another target: this peer's evidence starts anew
    }
    if (candidate) {
      s->evidence[k] = clampf(s->evidence[k] + llr - track_llr, p->evidence_max);
      in_range[peer_nb] = k;
      distance_m[peer_nb] = d_m;
      latest_m[peer_nb++] = peer->distance_m[peer->latest];
    }
  }
  float log_odds = -INFINITY;
  if (peer_nb > 0) {
    /* w_ok = rho_k exp(E_ok), rho_k = pi_k / (1 - 4 pi_k), each row divided by its largest entry (1 for the
     * wall) to stay finite */
    double log_rho[WALL_DETECTOR_MAX_PEERS];
    for (unsigned i = 0; i < peer_nb; i++) {
      const double pi = wall_detector_peer_prior(&p->model, distance_m[i]);
      log_rho[i] = log(pi / (1.0 - WALL_DETECTOR_SONAR_NB * pi));
    }
    double weight[WALL_DETECTOR_SONAR_NB][WALL_DETECTOR_MAX_PEERS + 1];
    double own_scale = 0.0;
    for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
      double log_w[WALL_DETECTOR_MAX_PEERS + 1] = { 0.0 };
      double largest = 0.0;
      for (unsigned i = 0; i < peer_nb; i++) {
        log_w[i + 1] = log_rho[i] + filter->sonars[o].evidence[in_range[i]];
        largest = fmax(largest, log_w[i + 1]);
      }
      for (unsigned i = 0; i <= peer_nb; i++) {
        weight[o][i] = exp(log_w[i] - largest);
      }
      if (o == sonar) {
        own_scale = largest;
      }
    }
    log_odds = assignment_log_odds(weight, own_scale, sonar, peer_nb);
  }

  decision->log_odds = log_odds;
  decision->confidence = 1.f / (1.f + expf(-fabsf(log_odds)));
  if (log_odds <= -p->wall_threshold) {
    decision->target_class = WALL_DETECTOR_WALL;
    remember_wall(p, sonar, s, range_m, pose, now_us, predicted_m, keep);
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
