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
  filter->llr_bound_model = params->model;
  filter->llr_bound = wall_detector_reading_llr_bound(&params->model);
}

/** wall_detector_reading_llr_bound of the filter's model, recomputed only after the model changed (a setting). */
static float llr_bound(struct wall_detector_filter *filter)
{
  if (memcmp(&filter->llr_bound_model, &filter->params.model, sizeof(filter->params.model)) != 0) {
    filter->llr_bound_model = filter->params.model;
    filter->llr_bound = wall_detector_reading_llr_bound(&filter->params.model);
  }
  return filter->llr_bound;
}

/**
 * The largest age (int32_t)(now_us - then_us) [us] that elapsed_s counts as within timeout_s: elapsed_s is
 * non-decreasing in the age, so elapsed_s(now_us, then_us) <= timeout_s exactly when the age is at most this
 * (INT32_MIN - 1 when no age is, e.g. for a NaN timeout). Lets the per-reading loops compare integers.
 */
static int64_t fresh_age_limit_us(float timeout_s)
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

/** True for a time at most fresh_age_limit_us old at now_us. */
static bool is_fresh(uint32_t then_us, uint32_t now_us, int64_t age_limit_us)
{
  return (int32_t)(now_us - then_us) <= age_limit_us;
}

/** Slot of a peer: its own, else a free one, else the one heard from longest ago. */
static int peer_slot(const struct wall_detector_filter *filter, uint16_t peer_id, uint32_t now_us)
{
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (filter->peers[i].used && filter->peers[i].id == peer_id) {
      return i;
    }
  }
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    if (!filter->peers[i].used) {
      return i;
    }
  }
  int stalest = 0;
  float stalest_age_s = -INFINITY;
  for (int i = 0; i < WALL_DETECTOR_MAX_PEERS; i++) {
    const struct wall_detector_peer *p = &filter->peers[i];
    const float age_s = elapsed_s(now_us, p->stamp_us[p->latest]);
    if (age_s > stalest_age_s) {
      stalest = i;
      stalest_age_s = age_s;
    }
  }
  return stalest;
}

/** True for a peer heard within the timeout whose newest distance is within the ranging range. */
static bool peer_fresh_in_range(const struct wall_detector_params *params, const struct wall_detector_peer *peer,
                                uint32_t now_us, int64_t age_limit_us)
{
  return peer->used && is_fresh(peer->stamp_us[peer->latest], now_us, age_limit_us) &&
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
  } else if (distance_m >= filter->params.model.ranging_max_m &&
             peer_fresh_in_range(&filter->params, peer, stamp_us, fresh_age_limit_us(filter->params.peer_timeout_s))) {
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

/**
 * The distance an echo of this peer is judged against, the median of its fresh distances, and the peer's prior
 * odds rho on one sonar there (both cached in the peer until its fresh distances or the copter radius change).
 * @return false when the peer cannot explain an echo now (unused, not heard within the timeout, out of range)
 */
static bool peer_distance(const struct wall_detector_params *params, struct wall_detector_peer *peer,
                          uint32_t now_us, int64_t age_limit_us, float *distance_m, double *prior_odds)
{
  if (!peer_fresh_in_range(params, peer, now_us, age_limit_us)) {
    return false;
  }
  uint8_t fresh = 0;
  for (int i = 0; i < peer->count; i++) {
    fresh |= (uint8_t)(is_fresh(peer->stamp_us[i], now_us, age_limit_us) << i);
  }
  if (fresh != peer->median_of) {
    peer->median_of = fresh;
    peer->median_m = median_distance(peer, fresh);
    peer->prior_radius_m = NAN;
  }
  if (peer->prior_radius_m != params->model.copter_radius_m) {
    peer->prior_radius_m = params->model.copter_radius_m;
    const double pi = wall_detector_peer_prior(&params->model, peer->median_m);
    peer->prior_odds = pi / (1.0 - WALL_DETECTOR_SONAR_NB * pi);
  }
  *distance_m = peer->median_m;
  *prior_odds = peer->prior_odds;
  return *distance_m < params->model.ranging_max_m;
}

/**
 * An angle wrapped into [-pi, pi] [rad]: remainderf(angle, 2 pi), which returns an angle within half a turn
 * unchanged (the nearest multiple of the turn is 0, a tie going to the even 0), so it is only called beyond.
 */
static float wrap_pi(float angle_rad)
{
  return fabsf(angle_rad) <= (float)M_PI ? angle_rad : remainderf(angle_rad, 2.f * (float)M_PI);
}

/** |a - b| wrapped into [0, pi] [rad]. */
static float yaw_change_rad(float a_rad, float b_rad)
{
  return fabsf(wrap_pi(a_rad - b_rad));
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
  const float dpsi_rad = yaw_change_rad(pose->yaw_rad, sonar->pose.yaw_rad);
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

/** Where the copter is along a sonar's boresight and across it (to its right) [m]. */
struct boresight_position {
  float along_m;
  float lateral_m;
};

/** Position of the copter along sonar `sonar`'s boresight (headings clockwise from the nose, a quarter turn apart). */
static struct boresight_position boresight_position(const struct wall_detector_pose *pose, int sonar)
{
  const float bearing_rad = pose->yaw_rad + (float)sonar * (float)(M_PI / 2.0);
  const float east = sinf(bearing_rad);
  const float north = cosf(bearing_rad);
  return (struct boresight_position) {
    .along_m = pose->x_m * east + pose->y_m * north,
    .lateral_m = pose->x_m * north - pose->y_m * east,
  };
}

/** wall_detector_filter_wall_prediction from the copter's position on the boresight and its heading. */
static void predict_wall(const struct wall_detector_params *params, const struct wall_detector_sonar *state,
                         struct boresight_position at, float yaw_rad, uint32_t now_us, float *predicted_m, float *keep)
{
  const float dt_s = fmaxf(elapsed_s(now_us, state->wall_stamp_us), 0.f);
  const float dpsi_rad = yaw_change_rad(yaw_rad, state->wall_last_yaw_rad);
  /* a wall is a line: reading + position along the boresight = a + slope x position across it (least squares
   * over the remembered readings, the slope shrunk toward 0, square to the beam, while the sideways spread is
   * small); a static wall reads closer by the own advance along the boresight */
  const float slope = state->wall_cov_m2 / (state->wall_lateral_var_m2 +
                      WALL_DETECTOR_TRACK_SPREAD * WALL_DETECTOR_TRACK_SPREAD);
  *predicted_m = state->wall_along_m + slope * (at.lateral_m - state->wall_lateral_m) - at.along_m;
  *keep = (1.f - params->model.outlier_prob) * expf(-dt_s / params->evidence_tau_s -
          fabsf(at.lateral_m - state->wall_last_lateral_m) / params->move_scale_m - dpsi_rad / params->turn_scale_rad);
}

bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep)
{
  if (!state->wall_known) {
    return false;
  }
  predict_wall(params, state, boresight_position(pose, sonar), pose->yaw_rad, now_us, predicted_m, keep);
  return true;
}

/**
 * Average a reading judged a wall into the sonar's remembered wall (its position along the boresight). A reading
 * off the remembered wall by more than the gate starts a new one only once the old one is half forgotten
 * (keep below half its most): a nearer echo in front of a wall still in view is rather a body between (whose
 * peer's ranging may lag) than another wall.
 */
static void remember_wall(const struct wall_detector_params *params, struct wall_detector_sonar *state,
                          float range_m, struct boresight_position at, float yaw_rad, uint32_t now_us,
                          float predicted_m, float keep)
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
  const float w = 1.f / state->wall_readings;
  const float d_wall_m = range_m + at.along_m - state->wall_along_m;
  const float d_lateral_m = at.lateral_m - state->wall_lateral_m;
  state->wall_along_m += w * d_wall_m;
  state->wall_lateral_m += w * d_lateral_m;
  state->wall_lateral_var_m2 = (1.f - w) * (state->wall_lateral_var_m2 + w * d_lateral_m * d_lateral_m);
  state->wall_cov_m2 = (1.f - w) * (state->wall_cov_m2 + w * d_lateral_m * d_wall_m);
  state->wall_last_lateral_m = at.lateral_m;
  state->wall_last_yaw_rad = yaw_rad;
  state->wall_stamp_us = now_us;
}

/*
 * The sums over assignments by a dynamic programme over the peers (each peer on one sonar at most, each sonar
 * seeing one peer at most): after peers 0..i-1, sum[taken] is the sum, over the ways of putting each of them on a
 * distinct sonar of the set `taken` (bit o: sonar o) or on none, of the product of their weights; the sonars not
 * taken see walls (weight 1). Every assignment of the four sonars is counted once, with positive terms only (no
 * subtraction to cancel when one weight dominates): the copter odds of sonar s are the sum over the sets holding s
 * against the sum over the others (the file comment's L, whose sums over A are both multiplied by the walls' 1).
 * peer_nb x 16 x 4 steps instead of (peer_nb + 1)^3 x peer_nb.
 */
double wall_detector_assignment_log_odds(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb, int sonar)
{
  enum { SET_NB = 1 << WALL_DETECTOR_SONAR_NB };
  double sum[SET_NB] = { 1.0 };  // no peer placed yet: the empty set only
  for (unsigned i = 0; i < peer_nb; i++) {
    /* a set gains the ways in which peer i is on one of its sonars o and the others on the rest (the set without
     * o, before peer i: sets in decreasing order, each read before it grows); i + 1 peers take i + 1 sonars at
     * most, larger sets stay empty */
#pragma GCC unroll 16
    for (int taken = SET_NB - 1; taken > 0; taken--) {
      if (__builtin_popcount((unsigned)taken) > (int)i + 1) {
        continue;
      }
      double gained = 0.0;
#pragma GCC unroll 4
      for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
        if (taken & (1 << o)) {
          gained += sum[taken & ~(1 << o)] * weight[i][o];
        }
      }
      sum[taken] += gained;
    }
  }
  /* each set without sonar s (its bits below s kept, those above moved up past it) and that set with s */
  const int own = 1 << sonar;
  double copter = 0.0, wall = 0.0;
  for (int rest = 0; rest < SET_NB / 2; rest++) {
    const int without = ((rest & ~(own - 1)) << 1) | (rest & (own - 1));
    wall += sum[without];
    copter += sum[without | own];
  }
  return log(copter / wall);
}

/** exp(E) of a sonar's evidence for a peer slot, from the sonar's cache when the evidence is the same. */
static double exp_evidence(struct wall_detector_sonar *state, int slot)
{
  if (!(state->exp_of[slot] == state->evidence[slot] && state->exp_evidence[slot] > 0.0)) {
    state->exp_of[slot] = state->evidence[slot];
    state->exp_evidence[slot] = exp(state->evidence[slot]);
  }
  return state->exp_evidence[slot];
}

/** The in-range peers of a reading: slots, median distances, newest distances and prior odds. */
struct in_range_peers {
  unsigned nb;
  int slot[WALL_DETECTOR_MAX_PEERS];
  float distance_m[WALL_DETECTOR_MAX_PEERS];
  float latest_m[WALL_DETECTOR_MAX_PEERS];  // the baseline judges by the newest distance, as the original
  double prior_odds[WALL_DETECTOR_MAX_PEERS];
};

/**
 * Update sonar `sonar`'s evidence for every peer with a reading (restarting it after a jump unless the peer
 * explains both targets) and list the peers in range. g is what the remembered wall says about the reading.
 */
static void update_evidence(struct wall_detector_filter *filter, int sonar, float range_m, float previous_m,
                            bool jumped, float track_llr, uint32_t now_us, struct in_range_peers *in_range)
{
  const struct wall_detector_params *p = &filter->params;
  struct wall_detector_sonar *s = &filter->sonars[sonar];
  const int64_t age_limit_us = fresh_age_limit_us(p->peer_timeout_s);
  /* a peer whose evidence is at the lower bound stays there when even the largest llr cannot lift it
   * ((E + llr) - g is non-decreasing in llr): its llr is not needed. Only a reading the remembered wall explains
   * well (g > 0) can pin it; +infinity: never. */
  const float pinning_llr = track_llr > 0.f && range_m > p->model.sonar_min_m ? llr_bound(filter) : INFINITY;
  in_range->nb = 0;
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    struct wall_detector_peer *peer = &filter->peers[k];
    float d_m = 0.f;
    double prior_odds = 0.0;
    const bool candidate = peer_distance(p, peer, now_us, age_limit_us, &d_m, &prior_odds);
    /* after a jump, keep a peer's evidence only if it favoured the peer and the jump went between that peer's
     * echo and its cross-talk (a facing copter's readings alternate between the two) */
    if (jumped && !(candidate && s->evidence[k] > 0.f && echo_and_crosstalk(&p->model, previous_m, range_m, d_m))) {
      s->evidence[k] = 0.f;  // another target: this peer's evidence starts anew
    }
    if (!candidate) {
      continue;
    }
    if (s->evidence[k] + pinning_llr - track_llr <= -p->evidence_max) {
      s->evidence[k] = -p->evidence_max;
    } else {
      const float llr = wall_detector_reading_llr(&p->model, range_m, d_m);
      s->evidence[k] = clampf(s->evidence[k] + llr - track_llr, p->evidence_max);
    }
    const unsigned i = in_range->nb++;
    in_range->slot[i] = k;
    in_range->distance_m[i] = d_m;
    in_range->latest_m[i] = peer->distance_m[peer->latest];
    in_range->prior_odds[i] = prior_odds;
  }
}

/** L of sonar `sonar` (file comment) over the peers in range: weights w_ok = rho_k exp(E_ok). */
static float copter_log_odds(struct wall_detector_filter *filter, int sonar, const struct in_range_peers *in_range)
{
  double weight[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];
  for (unsigned i = 0; i < in_range->nb; i++) {
    for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
      weight[i][o] = in_range->prior_odds[i] * exp_evidence(&filter->sonars[o], in_range->slot[i]);
    }
  }
  return (float)wall_detector_assignment_log_odds(weight, in_range->nb, sonar);
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
  const struct boresight_position at = boresight_position(pose, sonar);
  float track_llr = 0.f, predicted_m = 0.f, keep = 0.f;
  if (s->wall_known) {
    predict_wall(p, s, at, pose->yaw_rad, now_us, &predicted_m, &keep);
    track_llr = wall_detector_track_llr(&p->model, range_m, predicted_m, keep);
    if (range_m > predicted_m + WALL_DETECTOR_TRACK_GATE * p->model.track_sigma_m) {
      s->wall_known = false;  // an echo from beyond it: it was no wall
    }
  }

  struct in_range_peers in_range;
  update_evidence(filter, sonar, range_m, previous_m, jumped, track_llr, now_us, &in_range);
  const float log_odds = copter_log_odds(filter, sonar, &in_range);

  decision->log_odds = log_odds;
  decision->confidence = 1.f / (1.f + expf(-fabsf(log_odds)));
  if (log_odds <= -p->wall_threshold) {
    decision->target_class = WALL_DETECTOR_WALL;
    remember_wall(p, s, range_m, at, pose->yaw_rad, now_us, predicted_m, keep);
  } else if (log_odds >= p->copter_threshold) {
    decision->target_class = WALL_DETECTOR_COPTER;
    decision->attraction_m = range_m;
  } else {
    decision->target_class = WALL_DETECTOR_UNKNOWN;
  }
  decision->baseline_class = wall_detector_baseline_class(&p->model, range_m, in_range.latest_m, in_range.nb,
                             p->baseline_eps_m);
  return 0;
}

int wall_detector_sonar_index(float heading_rad)
{
  if (!isfinite(heading_rad)) {
    return -1;
  }
  /* front 0, right pi/2, back pi, left -pi/2: quarter turns clockwise (seen from above) from the front */
  const long quarter = lroundf(wrap_pi(heading_rad) / (float)(M_PI / 2.0));
  return (int)(((quarter % WALL_DETECTOR_SONAR_NB) + WALL_DETECTOR_SONAR_NB) % WALL_DETECTOR_SONAR_NB);
}
