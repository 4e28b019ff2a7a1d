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
 * @file modules/wall_detector/wall_detector_map.c
 * The wall map (its law: wall_detector_map.h).
 */

#include "modules/wall_detector/wall_detector_map.h"

#include <math.h>
#include <stddef.h>

_Static_assert(WALL_DETECTOR_MAX_PEERS <= 32, "the wall map keeps the peers that explain an echo as 32 bits");

struct wall_detector_map_beam wall_detector_map_beam_of(const struct wall_detector_pose *pose, float bearing_rad)
{
  return (struct wall_detector_map_beam) { pose->x_m, pose->y_m, sinf(bearing_rad), cosf(bearing_rad) };
}

/** Where a beam meets a line. */
struct meeting {
  bool met;         ///< the beam meets the line (file comment; else the rest may be unset)
  float range_m;    ///< r, where it should read [m]
  float var_m2;     ///< S, the variance of a reading about r without bulge [m^2]
  float s_m;        ///< the echo's place along the line from c [m]
  float cos_inc;    ///< n . u
};

/** d's variance now: it grew by the drift of the position estimate since the line's last echo, a random walk of
 * diffusion drift_m2_per_s (the integral of a velocity error correlated over a time much shorter than the minutes
 * a wall is remembered: 2 sd^2 tau, Groves 2013, section 14.2.6). */
static float offset_var_now(const struct wall_detector_map_line *line, const struct wall_detector_map_params *params,
                            uint32_t now_us)
{
  return line->p_dd_m2 + params->drift_m2_per_s * wall_detector_elapsed_nonnegative_s(now_us, line->stamp_us);
}

static struct meeting meet(const struct wall_detector_map_line *line, const struct wall_detector_map_params *params,
                           const struct wall_detector_model *model, const struct wall_detector_map_beam *beam,
                           uint32_t now_us)
{
  struct meeting m = { .met = false, .cos_inc = line->n_x * beam->u_x + line->n_y * beam->u_y };
  if (!line->used || m.cos_inc < WALL_DETECTOR_MAP_COS_INCIDENCE) {
    return m;
  }
  const float dx_m = beam->x_m - line->c_x_m, dy_m = beam->y_m - line->c_y_m;
  m.range_m = -(line->n_x * dx_m + line->n_y * dy_m) / m.cos_inc;
  m.s_m = line->n_y * (dx_m + m.range_m * beam->u_x) - line->n_x * (dy_m + m.range_m * beam->u_y);
  if (!(m.range_m > 0.f) || m.s_m < line->s_min_m - WALL_DETECTOR_MAP_REACH ||
      m.s_m > line->s_max_m + WALL_DETECTOR_MAP_REACH) {
    return m;
  }
  /* S = H P H' + sigma^2, H = (1, -s) / (n . u) */
  const float h_d = 1.f / m.cos_inc, h_t = -m.s_m / m.cos_inc;
  m.var_m2 = h_d * h_d * offset_var_now(line, params, now_us) + 2.f * h_d * h_t * line->p_dt_m +
             h_t * h_t * line->p_tt_rad2 + model->track_sigma_m * model->track_sigma_m;
  m.met = true;
  return m;
}

/** A wall, not a body: enough echoes, and no one peer explained more than the body share of them. */
static bool confirmed(const struct wall_detector_map_line *line)
{
  if (line->echoes < WALL_DETECTOR_MAP_CONFIRM) {
    return false;
  }
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    if (line->explained[k] > WALL_DETECTOR_MAP_BODY_SHARE * line->echoes) {
      return false;
    }
  }
  return true;
}

struct wall_detector_map_prediction wall_detector_map_predict(const struct wall_detector_map *map,
    const struct wall_detector_map_params *params, const struct wall_detector_model *model,
    const struct wall_detector_map_beam *beam, uint32_t now_us)
{
  struct meeting nearest = { .met = false, .range_m = INFINITY };
  int nearest_line = -1;
  for (int i = 0; i < WALL_DETECTOR_MAP_LINES; i++) {
    const struct meeting m = meet(&map->line[i], params, model, beam, now_us);
    if (m.met && m.range_m < nearest.range_m) {
      nearest = m;
      nearest_line = i;
    }
  }
  if (nearest_line < 0 || !confirmed(&map->line[nearest_line])) {
    return (struct wall_detector_map_prediction) { .known = false };
  }
  return (struct wall_detector_map_prediction) { true, nearest.range_m, nearest.var_m2 };
}

float wall_detector_map_ratio(const struct wall_detector_model_terms *terms,
                              const struct wall_detector_map_params *params,
                              const struct wall_detector_map_prediction *prediction, float range_m)
{
  const struct wall_detector_model *model = &terms->model;
  const float sd_m = sqrtf(prediction->var_m2);
  const float bulge_from_m = prediction->range_m - params->bulge_m;
  float ratio;  // p(reading | the mapped wall) / p(reading | a wall at an unknown range)
  if (!wall_detector_reading_clamped(model, range_m)) {
    const float z = (range_m - prediction->range_m) / sd_m;
    const float at_line = expf(-0.5f * z * z) / (sd_m * sqrtf(2.f * (float)M_PI));
    const float in_bulge = range_m >= bulge_from_m && range_m <= prediction->range_m ? 1.f / params->bulge_m : 0.f;
    ratio = (float)terms->span_m * ((1.f - params->bulge_prob) * at_line + params->bulge_prob * in_bulge);
  } else {
    /* P(reading <= minimum | the mapped wall) / P(reading <= minimum | a wall at an unknown range) */
    const float min_m = model->sonar_min_m;
    const float at_line = 0.5f * erfcf((prediction->range_m - min_m) / (sd_m * (float)M_SQRT2));
    const float in_bulge = fminf(fmaxf((min_m - bulge_from_m) / params->bulge_m, 0.f), 1.f);
    ratio = ((1.f - params->bulge_prob) * at_line + params->bulge_prob * in_bulge) / (float)terms->clamped_wall_p;
  }
  const float keep = 1.f - model->outlier_prob;
  return keep * ratio + (1.f - keep);
}

static void set_theta(struct wall_detector_map_line *line, float theta_rad)
{
  line->theta_rad = wall_detector_wrap_pi(theta_rad);
  line->n_x = sinf(line->theta_rad);
  line->n_y = cosf(line->theta_rad);
}

/** Count an echo fused, and for each peer that explained it (the counts halve before the echoes' would overflow:
 * the shares stay). */
static void count_echo(struct wall_detector_map_line *line, uint32_t explained_by)
{
  if (line->echoes == UINT16_MAX) {
    line->echoes /= 2;
    for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
      line->explained[k] /= 2;
    }
  }
  line->echoes++;
  for (int k = 0; k < WALL_DETECTOR_MAX_PEERS; k++) {
    line->explained[k] += (explained_by >> k) & 1u;
  }
}

/** Fuse an echo read range_m into the line it meets as m (file comment: c moved to the echo's place, the Kalman
 * update of (d, theta) there, c moved onto the updated line). */
static void fuse(struct wall_detector_map_line *line, const struct wall_detector_map_params *params,
                 const struct wall_detector_model *model, const struct meeting *m, float range_m, uint32_t now_us)
{
  const float s = m->s_m;
  float p_dd = offset_var_now(line, params, now_us) - 2.f * s * line->p_dt_m + s * s * line->p_tt_rad2;
  float p_dt = line->p_dt_m - s * line->p_tt_rad2;
  float p_tt = line->p_tt_rad2;
  line->c_x_m += s * line->n_y;
  line->c_y_m -= s * line->n_x;
  line->s_min_m = fminf(line->s_min_m - s, 0.f);
  line->s_max_m = fmaxf(line->s_max_m - s, 0.f);
  /* at the echo's place H = (1, 0) / (n . u): in units of d the innovation is (r - r0) (n . u) and the reading's
   * variance sigma^2 (n . u)^2 */
  const float noise_m2 = model->track_sigma_m * model->track_sigma_m * m->cos_inc * m->cos_inc;
  const float k_d = p_dd / (p_dd + noise_m2), k_t = p_dt / (p_dd + noise_m2);
  const float innovation_m = (range_m - m->range_m) * m->cos_inc;
  const float d_m = k_d * innovation_m;
  p_tt -= k_t * p_dt;
  p_dt -= k_d * p_dt;
  p_dd -= k_d * p_dd;
  line->c_x_m += d_m * line->n_x;
  line->c_y_m += d_m * line->n_y;
  set_theta(line, line->theta_rad + k_t * innovation_m);
  line->p_dd_m2 = p_dd;
  line->p_dt_m = p_dt;
  line->p_tt_rad2 = p_tt;
  line->stamp_us = now_us;
}

/** A new line through the echo, square to its beam. */
static void start(struct wall_detector_map_line *line, const struct wall_detector_map_params *params,
                  const struct wall_detector_model *model, const struct wall_detector_map_beam *beam, float range_m,
                  uint32_t now_us)
{
  *line = (struct wall_detector_map_line) {
    .used = true, .c_x_m = beam->x_m + range_m * beam->u_x, .c_y_m = beam->y_m + range_m * beam->u_y,
    .p_dd_m2 = model->track_sigma_m * model->track_sigma_m, .p_tt_rad2 = params->angle_sd_rad * params->angle_sd_rad,
    .stamp_us = now_us,
  };
  set_theta(line, atan2f(beam->u_x, beam->u_y));
}

/** The place of a new line: a free place, else that of an unconfirmed line, else of the line fused longest ago. */
static int place_for_a_new_line(const struct wall_detector_map *map)
{
  int unconfirmed = -1, oldest = 0;
  for (int i = 0; i < WALL_DETECTOR_MAP_LINES; i++) {
    const struct wall_detector_map_line *line = &map->line[i];
    if (!line->used) {
      return i;
    }
    if (unconfirmed < 0 && !confirmed(line)) {
      unconfirmed = i;
    }
    if ((int32_t)(line->stamp_us - map->line[oldest].stamp_us) < 0) {
      oldest = i;
    }
  }
  return unconfirmed >= 0 ? unconfirmed : oldest;
}

void wall_detector_map_learn(struct wall_detector_map *map, const struct wall_detector_map_params *params,
                             const struct wall_detector_model *model, const struct wall_detector_map_beam *beam,
                             float range_m, bool judged_wall, bool peers_in_range, uint32_t explained_by,
                             uint32_t crosstalk_of, uint32_t now_us)
{
  if (range_m < 2.f * model->copter_radius_m) {
    return;
  }
  int fused = -1;
  struct meeting fused_meeting = { .met = false };
  float fused_z = WALL_DETECTOR_MAP_GATE;
  bool in_front = false;
  for (int i = 0; i < WALL_DETECTOR_MAP_LINES; i++) {
    struct wall_detector_map_line *line = &map->line[i];
    const struct meeting m = meet(line, params, model, beam, now_us);
    if (m.met) {
      const float sd_m = sqrtf(m.var_m2);
      const float z = (range_m - m.range_m) / sd_m;
      const float radius_m = model->copter_radius_m;
      if (z > WALL_DETECTOR_MAP_GATE && m.s_m >= line->s_min_m - radius_m && m.s_m <= line->s_max_m + radius_m) {
        line->used = false;  // an echo from beyond it, where it was seen: it was no wall
      } else if (fabsf(z) <= fused_z) {
        fused = i;
        fused_z = fabsf(z);
        fused_meeting = m;
      } else if (z < 0.f &&
                 (confirmed(line) || range_m >= m.range_m - params->bulge_m - WALL_DETECTOR_MAP_GATE * sd_m)) {
        in_front = true;  // a body between the copter and a wall, or the wall's curtain bulging
      }
    }
  }
  if (!judged_wall && explained_by != 0u) {
    return;
  }
  /* an echo a peer explains, judged a wall all the same, fuses only into a line that predicts it sharply: one unseen
   * for long, its offset diffused, would jump onto the body the peer is and follow it */
  const float sharp_sd_m = WALL_DETECTOR_MAP_EXPLAINED_SD * model->ranging_sigma_m;
  if (fused >= 0 && explained_by != 0u && fused_meeting.var_m2 > sharp_sd_m * sharp_sd_m) {
    return;
  }
  struct wall_detector_map_line *line = NULL;
  if (fused >= 0) {
    line = &map->line[fused];
    fuse(line, params, model, &fused_meeting, range_m, now_us);
  } else if (!in_front) {
    line = &map->line[place_for_a_new_line(map)];
    start(line, params, model, beam, range_m, now_us);
  }
  if (line != NULL && peers_in_range) {
    count_echo(line, explained_by | crosstalk_of);   // only with a peer in range could one have explained it
  }
}
