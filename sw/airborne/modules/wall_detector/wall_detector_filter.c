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

#include <math.h>
#include <string.h>

static float clampf(float x, float bound)
{
  return x > bound ? bound : (x < -bound ? -bound : x);
}

/** The exponent -dt / tau - ds / move - dpsi / turn of the factor by which evidence or a remembered wall fades. */
static float fade_exponent(const struct wall_detector_params *params, float dt_s, float ds_m, float dpsi_rad)
{
  return -dt_s / params->evidence_tau_s - ds_m / params->move_scale_m - dpsi_rad / params->turn_scale_rad;
}

void wall_detector_filter_init(struct wall_detector_filter *filter, const struct wall_detector_params *params)
{
  memset(filter, 0, sizeof(*filter));
  filter->params = *params;
  wall_detector_model_terms_init(&filter->terms, &params->model);
  filter->llr_table = wall_detector_llr_table_shared(&filter->terms);
}

/** After a setting changed the model: its constants, and its table if one was built at init (building one here
 * could race with other copters' threads on the host; without one, the exact llr). */
static void follow_model(struct wall_detector_filter *filter)
{
  const struct wall_detector_model *model = &filter->params.model;
  if (memcmp(&filter->terms.model, model, sizeof(*model)) != 0) {
    wall_detector_model_terms_init(&filter->terms, model);
    filter->llr_table = wall_detector_llr_table_find(model);
  }
}

int wall_detector_filter_ranging(struct wall_detector_filter *filter, uint16_t peer_id, float distance_m,
                                 uint32_t stamp_us)
{
  if (!isfinite(distance_m) || distance_m < 0.f) {
    return -1;
  }
  bool is_new = false;
  const int slot = wall_detector_peers_record(&filter->peers, peer_id, distance_m, stamp_us,
                   filter->params.model.ranging_max_m, filter->params.peer_timeout_s, &is_new);
  if (slot >= 0 && is_new) {
    /* a new peer in this slot: its evidence starts from nothing */
    for (int s = 0; s < WALL_DETECTOR_SONAR_NB; s++) {
      filter->evidence[slot][s] = 0.f;
    }
  }
  return slot;
}

float wall_detector_filter_discount(const struct wall_detector_params *params,
                                    const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose,
                                    uint32_t now_us)
{
  if (!sonar->started) {
    return 0.f;
  }
  const float dt_s = wall_detector_elapsed_nonnegative_s(now_us, sonar->stamp_us);
  const float dx_m = pose->x_m - sonar->pose.x_m, dy_m = pose->y_m - sonar->pose.y_m;
  const float ds_m = sqrtf(dx_m * dx_m + dy_m * dy_m);
  const float dpsi_rad = wall_detector_yaw_change_rad(pose->yaw_rad, sonar->pose.yaw_rad);
  return expf(fade_exponent(params, dt_s, ds_m, dpsi_rad));
}

/** Where the copter is along a sonar's boresight and across it (to its right) [m]. */
struct boresight_position {
  float along_m;
  float lateral_m;
};

/** The beam of sonar `sonar`, whose bearing is the heading plus `sonar` quarter turns clockwise. */
static struct wall_detector_map_beam sonar_beam(const struct wall_detector_pose *pose, int sonar)
{
  return wall_detector_map_beam_of(pose, pose->yaw_rad + (float)sonar * (float)(M_PI / 2.0));
}

/** Position of the copter along a beam and across it (its unit boresight u: east, north). */
static struct boresight_position boresight_position(const struct wall_detector_map_beam *beam)
{
  return (struct boresight_position) {
    .along_m = beam->x_m * beam->u_x + beam->y_m * beam->u_y,
    .lateral_m = beam->x_m * beam->u_y - beam->y_m * beam->u_x,
  };
}

/** What a sonar's remembered wall predicts for a reading (wall_detector_filter_wall_prediction). */
struct wall_prediction {
  bool known;         ///< a wall is remembered (else the rest is 0)
  float predicted_m;  ///< where it should read [m]
  float keep;         ///< probability that a wall echo comes from it
};

/** The prediction of the wall the sonar remembers, for the copter at `at` with heading yaw_rad. */
static struct wall_prediction predict_wall(const struct wall_detector_params *params,
    const struct wall_detector_sonar *state, struct boresight_position at, float yaw_rad, uint32_t now_us)
{
  if (!state->wall_known) {
    return (struct wall_prediction) { .known = false };
  }
  /* a wall is a line: reading + position along the boresight = a + slope x position across it (least squares
   * over the remembered readings, the slope shrunk toward 0, square to the beam, while the sideways spread is
   * small); a static wall reads closer by the own advance along the boresight */
  const float slope = state->wall_cov_m2 / (state->wall_lateral_var_m2 +
                      WALL_DETECTOR_TRACK_SPREAD * WALL_DETECTOR_TRACK_SPREAD);
  const float dt_s = wall_detector_elapsed_nonnegative_s(now_us, state->wall_stamp_us);
  const float lateral_m = fabsf(at.lateral_m - state->wall_last_lateral_m);
  const float dpsi_rad = wall_detector_yaw_change_rad(yaw_rad, state->wall_last_yaw_rad);
  return (struct wall_prediction) {
    .known = true,
    .predicted_m = state->wall_along_m + slope * (at.lateral_m - state->wall_lateral_m) - at.along_m,
    .keep = (1.f - params->model.outlier_prob) * expf(fade_exponent(params, dt_s, lateral_m, dpsi_rad)),
  };
}

bool wall_detector_filter_wall_prediction(const struct wall_detector_params *params, int sonar,
    const struct wall_detector_sonar *state, const struct wall_detector_pose *pose, uint32_t now_us,
    float *predicted_m, float *keep)
{
  const struct wall_detector_map_beam beam = sonar_beam(pose, sonar);
  const struct wall_prediction wall = predict_wall(params, state, boresight_position(&beam), pose->yaw_rad, now_us);
  *predicted_m = wall.predicted_m;
  *keep = wall.keep;
  return wall.known;
}

/** g: what the remembered walls say about the reading (file comment), 0 where they know no wall. With the map, the
 * two memories' likelihood ratios averaged with equal weight: the echo comes from the wall the map predicts or from
 * the wall the sonar saw over the last 2 s. */
static float wall_llr(const struct wall_detector_filter *filter, const struct wall_detector_map_beam *beam,
                      const struct wall_prediction *wall, float range_m, uint32_t now_us)
{
  const struct wall_detector_params *p = &filter->params;
  /* each memory's ratio to a wall at an unknown range, 1 where it knows no wall */
  const float sonar_ratio = wall->known ?
                            wall_detector_track_ratio(&filter->terms, range_m, wall->predicted_m, wall->keep) : 1.f;
  if (!p->use_map) {
    return logf(sonar_ratio);
  }
  const struct wall_detector_map_prediction mapped = wall_detector_map_predict(&filter->map, &p->map, &p->model,
      beam, now_us);
  const float map_ratio = mapped.known ? wall_detector_map_ratio(&filter->terms, &p->map, &mapped, range_m) : 1.f;
  return logf(0.5f * (map_ratio + sonar_ratio));
}

/** Teach the wall map an echo of sonar `sonar` and its class, with the peers in range that explain it: as an echo
 * (explained_by, from update_evidence), or as the cross-talk of a peer the sonar's evidence favours (a facing
 * copter, whose readings alternate between its echo and its cross-talk). */
static void learn_map(struct wall_detector_filter *filter, int sonar, const struct wall_detector_map_beam *beam,
                      float range_m, bool judged_wall, uint32_t explained_by,
                      const struct wall_detector_candidates *in_range, uint32_t now_us)
{
  uint32_t crosstalk_of = 0u;
  for (unsigned i = 0; i < in_range->nb; i++) {
    const int k = in_range->slot[i];
    if (filter->evidence[k][sonar] > 0.f &&
        wall_detector_map_crosstalk_of(&filter->terms, range_m, in_range->distance_m[i])) {
      crosstalk_of |= 1u << k;
    }
  }
  const struct wall_detector_params *p = &filter->params;
  wall_detector_map_learn(&filter->map, &p->map, &p->model, beam, range_m, judged_wall, in_range->nb > 0,
                          explained_by, crosstalk_of, now_us);
}

/**
 * Average a reading judged a wall into the sonar's remembered wall (its position along the boresight). A reading
 * off the remembered wall by more than the gate starts a new one only once the old one is half forgotten
 * (keep below half its most): a nearer echo in front of a wall still in view is rather a body between (whose
 * peer's ranging may lag) than another wall.
 */
static void remember_wall(const struct wall_detector_params *params, struct wall_detector_sonar *state,
                          float range_m, struct boresight_position at, float yaw_rad, uint32_t now_us,
                          const struct wall_prediction *wall)
{
  if (!state->wall_known) {
    state->wall_known = true;
    state->wall_readings = 0;
  } else if (fabsf(range_m - wall->predicted_m) > WALL_DETECTOR_TRACK_GATE * params->model.track_sigma_m) {
    if (wall->keep > 0.5f * (1.f - params->model.outlier_prob)) {
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

/** True when the longer of two readings is best explained as peer_distance_m's echo. The shorter is then that
 * copter's cross-talk (its pulse, fired dt before ours, reads (path + c dt) / 2, before the echo whatever dt, and
 * unsynchronised rings keep dt for the flight: half the distance only when they fire together) or a short reading;
 * a wall cannot appear in front of a body the sonar sees. */
static bool echo_and_shorter(const struct wall_detector_model_terms *terms, float first_m, float second_m,
                             float peer_distance_m)
{
  return wall_detector_reading_part(terms, fmaxf(first_m, second_m), peer_distance_m) == WALL_DETECTOR_PART_ECHO;
}

/**
 * Update sonar `sonar`'s evidence, discounted already, with an echo: after a jump from previous_m, restart it where
 * the law says so; then add each peer in range's llr less g, within the bounds.
 * @return the peer slots that explain the echo (wall_detector_map_explains of their llr; bit k: slot k)
 */
static uint32_t update_evidence(struct wall_detector_filter *filter, int sonar, float range_m, float previous_m,
                                bool jumped, float g, const struct wall_detector_candidates *in_range)
{
  float (*evidence)[WALL_DETECTOR_SONAR_NB] = filter->evidence;
  if (jumped) {
    /* keep a peer's evidence only if it favoured the peer and the jump went between that peer's echo and a shorter
     * reading (a facing copter's readings alternate between its echo and its cross-talk); any other evidence starts
     * anew */
    bool keep[WALL_DETECTOR_MAX_PEERS] = { false };
    for (unsigned i = 0; i < in_range->nb; i++) {
      const int k = in_range->slot[i];
      keep[k] = evidence[k][sonar] > 0.f &&
                echo_and_shorter(&filter->terms, previous_m, range_m, in_range->distance_m[i]);
    }
    for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
      evidence[k][sonar] = keep[k] ? evidence[k][sonar] : 0.f;
    }
  }
  uint32_t explained_by = 0u;
  for (unsigned i = 0; i < in_range->nb; i++) {
    const int k = in_range->slot[i];
    const float llr = wall_detector_filter_reading_llr(filter, range_m, in_range->distance_m[i]);
    evidence[k][sonar] = clampf(evidence[k][sonar] + llr - g, filter->params.evidence_max);
    explained_by |= (uint32_t)wall_detector_map_explains(llr) << k;
  }
  return explained_by;
}

/** The posterior odds exp(L) that sonar `sonar` sees a copter and the confidence (file comment), from the weights
 * w_ok = rho_k exp(E_ok) of the peers in range. */
static void decide(const struct wall_detector_filter *filter, int sonar,
                   const struct wall_detector_candidates *in_range, struct wall_detector_decision *decision)
{
  double weight[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];
  for (unsigned i = 0; i < in_range->nb; i++) {
    for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
      weight[i][o] = in_range->prior_odds[i] * expf(filter->evidence[in_range->slot[i]][o]);
    }
  }
  double sum[WALL_DETECTOR_SONAR_SETS], confidence;
  wall_detector_assignment_sums(weight, in_range->nb, sum);
  wall_detector_assignment_sonar_decision(sum, sonar, &decision->odds, &confidence);
  decision->confidence = (float)confidence;
}

/** True when the pose estimate moved or turned farther since the sonar's previous reading than a copter can fly
 * (WALL_DETECTOR_MAP_JUMP_M plus WALL_DETECTOR_MAP_JUMP_SPEED over the time, WALL_DETECTOR_MAP_JUMP_RAD plus
 * WALL_DETECTOR_MAP_JUMP_YAW_RATE over the time): a new frame, as when an INS sets its origin at the first GPS fix
 * or an attitude filter aligns its heading. */
static bool position_jumped(const struct wall_detector_sonar *sonar, const struct wall_detector_pose *pose,
                            uint32_t now_us)
{
  if (!sonar->started) {
    return false;
  }
  const float dt_s = wall_detector_elapsed_nonnegative_s(now_us, sonar->stamp_us);
  const float dx_m = pose->x_m - sonar->pose.x_m, dy_m = pose->y_m - sonar->pose.y_m;
  const float reach_m = WALL_DETECTOR_MAP_JUMP_M + WALL_DETECTOR_MAP_JUMP_SPEED * dt_s;
  const float turn_rad = WALL_DETECTOR_MAP_JUMP_RAD + WALL_DETECTOR_MAP_JUMP_YAW_RATE * dt_s;
  return dx_m * dx_m + dy_m * dy_m > reach_m * reach_m ||
         wall_detector_yaw_change_rad(pose->yaw_rad, sonar->pose.yaw_rad) > turn_rad;
}

int wall_detector_filter_sonar(struct wall_detector_filter *filter, int sonar, float range_m,
                               const struct wall_detector_pose *pose, uint32_t now_us,
                               struct wall_detector_decision *decision)
{
  if (sonar < 0 || sonar >= WALL_DETECTOR_SONAR_NB || !isfinite(range_m) || range_m < 0.f) {
    return -1;
  }
  follow_model(filter);
  const struct wall_detector_params *p = &filter->params;
  struct wall_detector_sonar *s = &filter->sonars[sonar];
  if (position_jumped(s, pose, now_us)) {
    memset(&filter->map, 0, sizeof(filter->map));   // the remembered walls are in the old frame
  }
  /* every reading discounts the sonar's evidence */
  const float lambda = wall_detector_filter_discount(p, s, pose, now_us);
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    filter->evidence[k][sonar] *= lambda;
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
    decision->odds = 1.0;
    decision->confidence = 1.f;
    return 0;
  }
  const float previous_m = s->range_m;
  const bool jumped = fabsf(range_m - previous_m) > p->jump_m;
  s->range_m = range_m;

  struct wall_detector_candidates in_range;
  wall_detector_peers_candidates(&filter->peers, now_us, p->peer_timeout_s, &p->model, &in_range);
  /* what the remembered walls say: g (it weighs only against peers in range); an echo from beyond the sonar's
   * remembered wall shows it was no wall */
  const struct wall_detector_map_beam beam = sonar_beam(pose, sonar);
  const struct boresight_position at = boresight_position(&beam);
  const struct wall_prediction wall = predict_wall(p, s, at, pose->yaw_rad, now_us);
  const float g = in_range.nb > 0 ? wall_llr(filter, &beam, &wall, range_m, now_us) : 0.f;
  if (wall.known && range_m > wall.predicted_m + WALL_DETECTOR_TRACK_GATE * p->model.track_sigma_m) {
    s->wall_known = false;
  }
  const uint32_t explained_by = update_evidence(filter, sonar, range_m, previous_m, jumped, g, &in_range);
  decide(filter, sonar, &in_range, decision);
  const float log_odds = wall_detector_decision_log_odds(decision);
  if (log_odds <= -p->wall_threshold) {
    decision->target_class = WALL_DETECTOR_WALL;
    remember_wall(p, s, range_m, at, pose->yaw_rad, now_us, &wall);
  } else if (log_odds >= p->copter_threshold) {
    decision->target_class = WALL_DETECTOR_COPTER;
    decision->attraction_m = range_m;
  } else {
    decision->target_class = WALL_DETECTOR_UNKNOWN;
  }
  if (p->use_map) {
    learn_map(filter, sonar, &beam, range_m, decision->target_class == WALL_DETECTOR_WALL, explained_by, &in_range,
              now_us);
  }
  decision->baseline_class = wall_detector_baseline_class(&p->model, range_m, in_range.newest_m, in_range.nb,
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
  /* front 0, right pi/2, back pi, left -pi/2: the nearest whole number of quarter turns clockwise (seen from above)
   * from the front, halves away from zero */
  const long quarter = lroundf(wall_detector_wrap_pi(heading_rad) / (float)(M_PI / 2.0));
  return (int)((quarter + WALL_DETECTOR_SONAR_NB) % WALL_DETECTOR_SONAR_NB);
}
