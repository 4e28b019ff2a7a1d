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
 * Sequence filter of the wall detector (see wall_detector_filter.h for the law): each sonar's evidence, its
 * remembered wall, the decision.
 */

#include "modules/wall_detector/wall_detector_filter.h"
#include "modules/wall_detector/wall_detector_bounds.h"

#include <math.h>
#include <string.h>

static float clampf(float x, float bound)
{
  return x > bound ? bound : (x < -bound ? -bound : x);
}

/** The fading rates of the params' scales. */
static struct wall_detector_fade fade_of(const struct wall_detector_params *params)
{
  return (struct wall_detector_fade) {
    .per_s = 1.f / params->evidence_tau_s, .per_m = 1.f / params->move_scale_m, .per_rad = 1.f / params->turn_scale_rad,
  };
}

/** Bring the caches derived from the params' scales and thresholds up to them. */
static void derive_scales_and_thresholds(struct wall_detector_filter *filter)
{
  const struct wall_detector_params *p = &filter->params;
  filter->fade = fade_of(p);
  filter->wall_band = wall_detector_odds_band_of(-p->wall_threshold);
  filter->copter_band = wall_detector_odds_band_of(p->copter_threshold);
}

/** The exponent -dt / tau - ds / move - dpsi / turn of the factor exp(.) by which evidence or a remembered wall fades
 * (file comment). */
static float fade_exponent(const struct wall_detector_fade *fade, float dt_s, float ds_m, float dpsi_rad)
{
  return -dt_s * fade->per_s - ds_m * fade->per_m - dpsi_rad * fade->per_rad;
}

void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params)
{
  memset(filter, 0, sizeof(*filter));
  filter->params = *params;
  wall_detector_model_terms_init(&filter->terms, &params->model);
  filter->llr_table = wall_detector_llr_table_shared(&filter->terms);
  filter->age_limit_of_s = params->peer_timeout_s;
  filter->age_limit_us = wall_detector_fresh_age_limit_us(params->peer_timeout_s);
  derive_scales_and_thresholds(filter);
  filter->settings_of = *params;
}

/** Recompute the freshness limit of the timeout (and the peers' fresh distances) when the timeout changed. */
static void follow_timeout(struct wall_detector_filter *filter)
{
  const float timeout_s = filter->params.peer_timeout_s;
  if (memcmp(&filter->age_limit_of_s, &timeout_s, sizeof(float)) != 0) {
    filter->age_limit_of_s = timeout_s;
    filter->age_limit_us = wall_detector_fresh_age_limit_us(timeout_s);
    wall_detector_peers_timeout_changed(&filter->peers);
  }
}

/** Recompute what the filter derived from its settings when one changed (a setting's bits differ from those the
 * caches are of): the model's terms and llr table (a table built at init for that model, else none: the exact
 * llr; building one here could race with other copters' threads) and what the peers derived from the model, when
 * the model changed; the freshness limit of the timeout (follow_timeout); the fading rates and the odds bands. */
static void follow_settings(struct wall_detector_filter *filter)
{
  const struct wall_detector_params *p = &filter->params;
  if (memcmp(&filter->settings_of, p, sizeof(*p)) == 0) {
    return;
  }
  if (memcmp(&filter->terms.model, &p->model, sizeof(p->model)) != 0) {
    wall_detector_model_terms_init(&filter->terms, &p->model);
    filter->llr_table = wall_detector_llr_table_find(&p->model);
    wall_detector_peers_model_changed(&filter->peers);
  }
  follow_timeout(filter);
  derive_scales_and_thresholds(filter);
  filter->settings_of = *p;
}

int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                 uint32_t stamp_us)
{
  if (!isfinite(distance_m) || distance_m < 0.f) {
    return -1;
  }
  /* recording needs only the timeout's freshness limit (and the ranging maximum, read from the params): what the
   * filter derived from the model and the scales serves the readings, whose follow_settings brings it up to date
   * before it is used */
  follow_timeout(filter);
  bool is_new = false;
  const int slot = wall_detector_peers_record(&filter->peers, peer_id, distance_m, stamp_us,
                   filter->params.model.ranging_max_m, filter->age_limit_us, &is_new);
  if (slot >= 0 && is_new) {
    /* a new peer in this slot: its evidence starts from nothing */
    for (int s = 0; s < WALL_DETECTOR_SONAR_NB; s++) {
      filter->evidence[slot][s] = 0.f;
    }
  }
  return slot;
}


/** The exponent of the discount of a sonar's evidence, lambda = expf(exponent) (file comment); 0 (unused: its
 * discount is 0, discount_of) before the sonar's first reading. */
static float discount_exponent(const struct wall_detector_fade *fade, const struct wall_detector_sonar *sonar,
                               const struct wall_detector_pose *pose, uint32_t now_us)
{
  if (!sonar->started) {
    return 0.f;
  }
  const float dt_s = wall_detector_elapsed_nonnegative_s(now_us, sonar->stamp_us);
  const float dx_m = pose->x_m - sonar->pose.x_m, dy_m = pose->y_m - sonar->pose.y_m;
  const float ds_m = sqrtf(dx_m * dx_m + dy_m * dy_m);  // float precision: hypotf's overflow care is not needed
  const float dpsi_rad = wall_detector_yaw_change_rad(pose->yaw_rad, sonar->pose.yaw_rad);
  return fade_exponent(fade, dt_s, ds_m, dpsi_rad);
}

/** The discount lambda = expf(discount_exp) of a started sonar's evidence, 0 before its first reading. */
static float discount_of(bool started, float discount_exp)
{
  return started ? expf(discount_exp) : 0.f;
}

float wall_detector_filter_discount(const struct wall_detector_params *params,
                                    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose,
                                    uint32_t now_us)
{
  const struct wall_detector_fade fade = fade_of(params);
  return discount_of(sonar->started, discount_exponent(&fade, sonar, pose, now_us));
}

/** True when one of two readings is best explained as peer_distance_m's echo and the other as its cross-talk. */
static bool echo_and_crosstalk(const struct wall_detector_model_terms *terms, float first_m, float second_m,
                               float peer_distance_m)
{
  const enum wall_detector_part a = wall_detector_reading_part(terms, first_m, peer_distance_m);
  const enum wall_detector_part b = wall_detector_reading_part(terms, second_m, peer_distance_m);
  return (a == WALL_DETECTOR_PART_ECHO && b == WALL_DETECTOR_PART_CROSSTALK) ||
         (a == WALL_DETECTOR_PART_CROSSTALK && b == WALL_DETECTOR_PART_ECHO);
}

/** Where the copter is along a sonar's boresight and across it (to its right) [m]. */
struct boresight_position {
  float along_m;
  float lateral_m;
};

/** Bearing of sonar `sonar`'s boresight, clockwise from north (headings clockwise from the nose, a quarter turn
 * apart) [rad]. */
static float boresight_bearing_rad(const struct wall_detector_pose *pose, int sonar)
{
  return pose->yaw_rad + (float)sonar * (float)(M_PI / 2.0);
}

/** Position of the copter along and across a boresight of bearing (sin, cos) = (east, north). */
static struct boresight_position position_on_boresight(const struct wall_detector_pose *pose, float east, float north)
{
  return (struct boresight_position) {
    .along_m = pose->x_m * east + pose->y_m * north,
    .lateral_m = pose->x_m * north - pose->y_m * east,
  };
}

/** Position of the copter along sonar `sonar`'s boresight. */
static struct boresight_position boresight_position(const struct wall_detector_pose *pose, int sonar)
{
  const float bearing_rad = boresight_bearing_rad(pose, sonar);
  return position_on_boresight(pose, sinf(bearing_rad), cosf(bearing_rad));
}

/** boresight_position, with the sine and cosine of the bearing kept in the sonar's state and computed again only
 * when the bearing's bits change (the copter's heading seldom does). */
static struct boresight_position boresight_position_cached(struct wall_detector_sonar *state,
    const struct wall_detector_pose *pose, int sonar)
{
  wall_detector_bearing_update(&state->boresight, boresight_bearing_rad(pose, sonar));
  return position_on_boresight(pose, state->boresight.sin_b, state->boresight.cos_b);
}

/** The probability keep of wall_detector_filter_wall_prediction from its fading exponent (predict_wall). */
static float keep_of(const struct wall_detector_params *params, float keep_exponent)
{
  return (1.f - params->model.outlier_prob) * expf(keep_exponent);
}

/** wall_detector_filter_wall_prediction from the copter's position on the boresight and its heading, with the
 * fading exponent of keep (keep_of) in its place. */
static void predict_wall(const struct wall_detector_fade *fade, const struct wall_detector_sonar *state,
                         struct boresight_position at, float yaw_rad, uint32_t now_us, float *predicted_m,
                         float *keep_exponent)
{
  const float dt_s = wall_detector_elapsed_nonnegative_s(now_us, state->wall_stamp_us);
  const float dpsi_rad = wall_detector_yaw_change_rad(yaw_rad, state->wall_last_yaw_rad);
  /* a wall is a line: reading + position along the boresight = a + slope x position across it (least squares
   * over the remembered readings, the slope shrunk toward 0, square to the beam, while the sideways spread is
   * small); a static wall reads closer by the own advance along the boresight */
  const float slope = state->wall_cov_m2 / (state->wall_lateral_var_m2 +
                      WALL_DETECTOR_TRACK_SPREAD * WALL_DETECTOR_TRACK_SPREAD);
  *predicted_m = state->wall_along_m + slope * (at.lateral_m - state->wall_lateral_m) - at.along_m;
  *keep_exponent = fade_exponent(fade, dt_s, fabsf(at.lateral_m - state->wall_last_lateral_m), dpsi_rad);
}

bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep)
{
  if (!state->wall_known) {
    return false;
  }
  const struct wall_detector_fade fade = fade_of(params);
  float keep_exponent;
  predict_wall(&fade, state, boresight_position(pose, sonar), pose->yaw_rad, now_us, predicted_m, &keep_exponent);
  *keep = keep_of(params, keep_exponent);
  return true;
}

/**
 * Average a reading judged a wall into the sonar's remembered wall (its position along the boresight). A reading
 * off the remembered wall by more than the gate starts a new one only once the old one is half forgotten
 * (keep below half its most): a nearer echo in front of a wall still in view is rather a body between (whose
 * peer's ranging may lag) than another wall. keep is given by its fading exponent (predict_wall).
 */
static void remember_wall(const struct wall_detector_params *params, struct wall_detector_sonar *state,
                          float range_m, struct boresight_position at, float yaw_rad, uint32_t now_us,
                          float predicted_m, float keep_exponent)
{
  if (!state->wall_known) {
    state->wall_known = true;
    state->wall_readings = 0;
  } else if (fabsf(range_m - predicted_m) > WALL_DETECTOR_TRACK_GATE * params->model.track_sigma_m) {
    if (keep_of(params, keep_exponent) > 0.5f * (1.f - params->model.outlier_prob)) {
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

/** exp(E) of sonar o's evidence for a peer slot, from the cache when the evidence is the same (in float: a
 * relative error of 6e-8, the log-odds' 1e-7). */
static double exp_evidence(struct wall_detector_filter *filter, int slot, int o)
{
  if (!(filter->exp_of[slot][o] == filter->evidence[slot][o] && filter->exp_evidence[slot][o] > 0.0)) {
    filter->exp_of[slot][o] = filter->evidence[slot][o];
    filter->exp_evidence[slot][o] = expf(filter->evidence[slot][o]);
  }
  return filter->exp_evidence[slot][o];
}

float wall_detector_filter_reading_llr(const struct wall_detector_filter *filter, float range_m,
                                      float peer_distance_m)
{
  if (filter->llr_table == NULL) {
    return wall_detector_reading_llr(&filter->terms, range_m, peer_distance_m);
  }
  return wall_detector_reading_clamped(&filter->terms.model, range_m) ?
         wall_detector_llr_table_clamped_llr(filter->llr_table, peer_distance_m) :
         wall_detector_llr_table_llr(filter->llr_table, range_m, peer_distance_m);
}

/** Multiply sonar `sonar`'s evidence for every slot by the discount (discount_of). */
static void discount_evidence(struct wall_detector_filter *filter, int sonar, bool started, float discount_exp)
{
  const float lambda = discount_of(started, discount_exp);
#pragma GCC unroll 8
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    filter->evidence[k][sonar] *= lambda;
  }
}

/** The upper bound of the llr of a reading above the minimum (of the table when the filter uses one). */
static float llr_bound(const struct wall_detector_filter *filter)
{
  return filter->llr_table != NULL ? filter->llr_table->llr_bound : filter->terms.llr_bound;
}

/** The llr bound that pins a peer's evidence at the lower bound (update_evidence): +infinity when no llr can. */
static float pinning_llr(const struct wall_detector_filter *filter, bool clamped, float track_llr)
{
  return track_llr > 0.f && !clamped ? llr_bound(filter) : INFINITY;
}

/**
 * A peer's evidence after a reading above the minimum that does not pin it: clamp(E + llr - g, +-evidence_max)
 * with E discounted already. With the shared table, the llr's logf is skipped where its bounds
 * (wall_detector_bounds.h) put the sum beyond a bound of the evidence either way: float rounding is monotone, so
 * the exact sum is beyond it too, and the clamp gives the bound whatever the llr's last digits.
 */
static float updated_evidence(const struct wall_detector_filter *filter, float discounted, float range_m,
                              float peer_distance_m, float track_llr)
{
  const float max = filter->params.evidence_max;
  const struct wall_detector_llr_table *table = filter->llr_table;
  if (table == NULL || wall_detector_reading_clamped(&filter->terms.model, range_m)) {
    return clampf(discounted + wall_detector_filter_reading_llr(filter, range_m, peer_distance_m) - track_llr, max);
  }
  const float ratio = wall_detector_llr_table_ratio(table, range_m, peer_distance_m);
  if (ratio != table->model.outlier_prob) {   // else its llr is known without logf
    if (discounted + wall_detector_logf_lower_bound(ratio) - track_llr >= max) {
      return max;
    }
    if (discounted + wall_detector_logf_upper_bound(ratio) - track_llr <= -max) {
      return -max;
    }
  }
  return clampf(discounted + wall_detector_llr_table_llr_of_ratio(table, ratio) - track_llr, max);
}

/**
 * Update sonar `sonar`'s evidence, discounted already, for every peer in range with a reading (restarting it after
 * a jump unless the peer explains both targets). g is what the remembered wall says about the reading.
 */
static void update_evidence(struct wall_detector_filter *filter, int sonar, float range_m, float previous_m,
                            bool jumped, float track_llr, const struct wall_detector_candidates *in_range)
{
  const struct wall_detector_params *p = &filter->params;
  const struct wall_detector_model_terms *terms = &filter->terms;
  float (*evidence)[WALL_DETECTOR_SONAR_NB] = filter->evidence;
  if (jumped) {
    /* after a jump, keep a peer's evidence only if it favoured the peer and the jump went between that peer's
     * echo and its cross-talk (a facing copter's readings alternate between the two); other peers' evidence
     * starts anew (another target) */
    bool keep[WALL_DETECTOR_MAX_PEERS] = { false };
    for (unsigned i = 0; i < in_range->nb; i++) {
      const int k = in_range->slot[i];
      keep[k] = evidence[k][sonar] > 0.f && echo_and_crosstalk(terms, previous_m, range_m, in_range->distance_m[i]);
    }
    for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
      evidence[k][sonar] = keep[k] ? evidence[k][sonar] : 0.f;
    }
  }
  /* a peer whose evidence is at the lower bound stays there when even the largest llr cannot lift it
   * ((E + llr) - g is non-decreasing in llr): its llr is not needed. Only a reading the remembered wall explains
   * well (g > 0) can pin it; +infinity: never (the bound is of readings above the minimum). */
  const float pinning = pinning_llr(filter, wall_detector_reading_clamped(&p->model, range_m), track_llr);
  for (unsigned i = 0; i < in_range->nb; i++) {
    const int k = in_range->slot[i];
    if (evidence[k][sonar] + pinning - track_llr <= -p->evidence_max) {
      evidence[k][sonar] = -p->evidence_max;
    } else {
      evidence[k][sonar] = updated_evidence(filter, evidence[k][sonar], range_m, in_range->distance_m[i], track_llr);
    }
  }
}

bool wall_detector_filter_surely_pinned(const struct wall_detector_filter *filter, float evidence, float range_m,
                                        float predicted_m, float discount_exp, float keep_exp)
{
  const struct wall_detector_params *p = &filter->params;
  if (wall_detector_reading_clamped(&p->model, range_m) || !(discount_exp <= 0.f) || !(keep_exp <= 0.f)) {
    return false;
  }
  /* a sum of the exponents, valid where it is > 0 (the test below); a NaN or -infinity exponent fails the test */
  const float g_lo = wall_detector_track_llr_lower_bound(&filter->terms, range_m, predicted_m, keep_exp);
  /* lambda <= 1 (its exponent is <= 0), so lambda E <= E for E >= 0, and lambda E <= lambda_lo E for E < 0 */
  const float discounted_hi = evidence < 0.f ? evidence * wall_detector_expf_lower_bound(discount_exp) : evidence;
  return g_lo > 0.f && discounted_hi + llr_bound(filter) - g_lo <= -p->evidence_max;
}

/**
 * True when every peer in range is surely pinned at the lower bound by this reading
 * (wall_detector_filter_surely_pinned: the pinning test is monotone in the evidence, so that of the largest decides
 * for all) and every slot out of range holds no peer, so its evidence is 0 (filter->evidence), which the discount
 * leaves as it is: the reading then needs neither the discount nor the track llr.
 */
static bool surely_all_pinned(const struct wall_detector_filter *filter, int sonar, float range_m, float discount_exp,
                              float predicted_m, float keep_exp, const struct wall_detector_candidates *in_range)
{
  if (in_range->nb == 0 || (filter->peers.used_slots & ~in_range->slot_set) != 0) {
    return false;  // no peer to pin, or a peer out of range whose evidence needs the discount
  }
  float largest = filter->evidence[in_range->slot[0]][sonar];
  for (unsigned i = 1; i < in_range->nb; i++) {
    const float evidence = filter->evidence[in_range->slot[i]][sonar];
    largest = evidence > largest ? evidence : largest;
  }
  return wall_detector_filter_surely_pinned(filter, largest, range_m, predicted_m, discount_exp, keep_exp);
}

/** The bits of a float and of a double (cache keys compare bits: the same bits give the same results). */
static uint32_t float_bits(float x)
{
  uint32_t bits;
  memcpy(&bits, &x, sizeof(bits));
  return bits;
}

static uint64_t double_bits(double x)
{
  uint64_t bits;
  memcpy(&bits, &x, sizeof(bits));
  return bits;
}

/** Nonzero when the i-th peer in range is not the one of the cached weights in row i, or has other prior odds. */
static uint64_t peer_differs(const struct wall_detector_decision_cache *c,
                             const struct wall_detector_candidates *in_range, unsigned i)
{
  return (uint64_t)(c->slot[i] != in_range->slot[i]) |
         (double_bits(c->prior_odds[i]) ^ double_bits(in_range->prior_odds[i]));
}

/**
 * Bring the cached weights w_ok = rho_k exp(E_ok) to the peers in range and their evidence, in one pass: an entry
 * whose peer, prior odds and evidence are those it was computed from is kept (the same inputs give the same
 * weight). A row's four evidence bits are compared at once; only a row that differs is looked at entry by entry.
 * The rows' peers are compared with the list only when it was listed again since they were brought to it (each
 * pass leaves every row with its list's peer and prior odds).
 * @return true when an entry was recomputed or the number of peers changed
 */
static bool update_weights(struct wall_detector_filter *filter, const struct wall_detector_candidates *in_range)
{
  struct wall_detector_decision_cache *c = &filter->decision;
  const bool same_list = c->listing_of == filter->peers.candidates_listing;
  bool changed = c->peer_nb != in_range->nb;
  c->peer_nb = in_range->nb;
  c->listing_of = filter->peers.candidates_listing;
  for (unsigned i = 0; i < in_range->nb; i++) {
    const int k = in_range->slot[i];
    const bool same_peer = same_list || peer_differs(c, in_range, i) == 0;
    if (same_peer && memcmp(c->evidence[i], filter->evidence[k], sizeof(c->evidence[i])) == 0) {
      continue;
    }
    changed = true;
    c->slot[i] = k;
    c->prior_odds[i] = in_range->prior_odds[i];
    for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
      if (!same_peer || float_bits(c->evidence[i][o]) != float_bits(filter->evidence[k][o])) {
        c->evidence[i][o] = filter->evidence[k][o];
        c->weight[i][o] = c->prior_odds[i] * exp_evidence(filter, k, o);
      }
    }
  }
  return changed;
}

/** exp(L) of sonar `sonar` (file comment) over the peers in range and its confidence 1 / (1 + exp(-|L|)), found
 * again only when a weight changed since they were found. */
static void copter_odds(struct wall_detector_filter *filter, int sonar,
                            const struct wall_detector_candidates *in_range, struct wall_detector_decision *decision)
{
  struct wall_detector_decision_cache *c = &filter->decision;
  if (update_weights(filter, in_range) || !c->summed) {
    wall_detector_assignment_sums(c->weight, c->peer_nb, c->sum);
    c->summed = true;
    memset(c->found, 0, sizeof(c->found));
  }
  if (!c->found[sonar]) {
    double confidence;
    wall_detector_assignment_sonar_decision(c->sum, sonar, &c->odds[sonar], &confidence);
    c->confidence[sonar] = (float)confidence;
    c->found[sonar] = true;
  }
  decision->odds = c->odds[sonar];
  decision->confidence = c->confidence[sonar];
}

int wall_detector_filter_sonar(struct wall_detector_filter *filter, int sonar, float range_m,
                               const struct wall_detector_pose *pose, uint32_t now_us,
                               struct wall_detector_decision *decision)
{
  if (sonar < 0 || sonar >= WALL_DETECTOR_SONAR_NB || !isfinite(range_m) || range_m < 0.f) {
    return -1;
  }
  follow_settings(filter);
  const struct wall_detector_params *p = &filter->params;
  struct wall_detector_sonar *s = &filter->sonars[sonar];
  /* the discount's exponent (discount_evidence) */
  const bool started = s->started;
  const float discount_exp = discount_exponent(&filter->fade, s, pose, now_us);
  s->started = true;
  s->stamp_us = now_us;
  s->pose = *pose;

  decision->repulsion_m = range_m;
  decision->attraction_m = -1.f;
  if (!wall_detector_is_echo(&p->model, range_m)) {
    /* nothing hit: no evidence either way, and the next echo is compared with the last one */
    discount_evidence(filter, sonar, started, discount_exp);
    decision->target_class = WALL_DETECTOR_NO_ECHO;
    decision->baseline_class = WALL_DETECTOR_NO_ECHO;
    decision->odds = 1.0;
    decision->confidence = 1.f;
    return 0;
  }
  const bool jumped = fabsf(range_m - s->range_m) > p->jump_m;
  const float previous_m = s->range_m;
  s->range_m = range_m;

  const struct wall_detector_candidates *in_range = wall_detector_peers_candidates(&filter->peers, now_us,
      filter->age_limit_us, &p->model);
  /* where the remembered wall should read, and the fading exponent of keep */
  const struct boresight_position at = boresight_position_cached(s, pose, sonar);
  const bool wall_known = s->wall_known;
  float predicted_m = 0.f, keep_exp = 0.f;
  if (wall_known) {
    predict_wall(&filter->fade, s, at, pose->yaw_rad, now_us, &predicted_m, &keep_exp);
    if (range_m > predicted_m + WALL_DETECTOR_TRACK_GATE * p->model.track_sigma_m) {
      s->wall_known = false;  // an echo from beyond it: it was no wall
    }
  }

  if (started && !jumped && wall_known &&
      surely_all_pinned(filter, sonar, range_m, discount_exp, predicted_m, keep_exp, in_range)) {
    for (unsigned i = 0; i < in_range->nb; i++) {
      filter->evidence[in_range->slot[i]][sonar] = -p->evidence_max;
    }
  } else {
    discount_evidence(filter, sonar, started, discount_exp);
    /* what the remembered wall says (the same for every peer; g is needed only with a peer in range) */
    const float track_llr = wall_known && in_range->nb > 0 ?
                            wall_detector_track_llr(&filter->terms, range_m, predicted_m, keep_of(p, keep_exp)) : 0.f;
    update_evidence(filter, sonar, range_m, previous_m, jumped, track_llr, in_range);
  }
  copter_odds(filter, sonar, in_range, decision);
  if (wall_detector_log_odds_at_most(decision->odds, -p->wall_threshold, &filter->wall_band)) {
    decision->target_class = WALL_DETECTOR_WALL;
    remember_wall(p, s, range_m, at, pose->yaw_rad, now_us, predicted_m, keep_exp);
  } else if (wall_detector_log_odds_at_least(decision->odds, p->copter_threshold, &filter->copter_band)) {
    decision->target_class = WALL_DETECTOR_COPTER;
    decision->attraction_m = range_m;
  } else {
    decision->target_class = WALL_DETECTOR_UNKNOWN;
  }
  decision->baseline_class = wall_detector_baseline_class(&p->model, range_m, in_range->newest_m, in_range->nb,
                             p->baseline_eps_m);
  return 0;
}

float wall_detector_decision_log_odds(const struct wall_detector_decision *decision)
{
  return (float)log(decision->odds);
}

int wall_detector_sonar_index(float heading_rad)
{
  if (!isfinite(heading_rad)) {
    return -1;
  }
  /* front 0, right pi/2, back pi, left -pi/2: quarter turns clockwise (seen from above) from the front, the
   * nearest whole number of them (halves away from zero, as lroundf) to q in [-2, 2] (|wrapped| <= pi) */
  const float q = wall_detector_wrap_pi(heading_rad) / (float)(M_PI / 2.0);
  const int quarter = (q >= 1.5f) + (q >= 0.5f) + (q > -0.5f) + (q > -1.5f) - 2;  // -2..2, without branches
  return (quarter + WALL_DETECTOR_SONAR_NB) % WALL_DETECTOR_SONAR_NB;
}
