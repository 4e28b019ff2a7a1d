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
 * @file modules/wall_detector/wall_detector_reading.c
 * Per-reading error model of a copter echo, its log-likelihood ratio against a wall, the remembered wall's
 * prediction, the prior of a peer on a boresight, and the baseline check.
 */

#include "modules/wall_detector/wall_detector_reading.h"

#include <math.h>

/** 1 / sqrt(2 pi) */
#define WALL_DETECTOR_INV_SQRT_2PI 0.3989422804014327

/** Standard normal cumulative distribution function. */
static double normal_cdf(double z)
{
  return 0.5 * erfc(-z / M_SQRT2);
}

/** The shortfall's constants for (s, r) (each as the formulas below compute it). */
static struct wall_detector_shortfall shortfall_of(double sonar_sigma_m, double ranging_sigma_m)
{
  const double s = sonar_sigma_m;
  const double r = ranging_sigma_m;
  const double v2 = s * s + r * r;
  const double v = sqrt(v2);
  return (struct wall_detector_shortfall) {
    .s = s, .r = r, .v2 = v2, .v3 = v2 * v, .rv = r * v, .two_r2 = 2.0 * r * r, .two_v2 = 2.0 * v2,
    .gauss_coef = r / v2 * WALL_DETECTOR_INV_SQRT_2PI, .s_over_v = s / v,
  };
}

/*
 * Shortfall density, u = R + n with R ~ Rayleigh(s), n ~ N(0, r^2):
 *   p(u) = int_0^inf (x / s^2) exp(-x^2 / (2 s^2)) phi_r(u - x) dx.
 * Completing the square in x (v^2 = s^2 + r^2) turns the integrand into a Gaussian in x with mean
 * u s^2 / v^2 and standard deviation s r / v, and int_0^inf x N(x; m, w^2) dx = w phi(m / w) + m Phi(m / w):
 *   p(u) = r / (v^2 sqrt(2 pi)) exp(-u^2 / (2 r^2)) + (u s / v^3) Phi(u s / (r v)) exp(-u^2 / (2 v^2)).
 * As r -> 0 it tends to the Rayleigh density; it integrates to 1 and has mean s sqrt(pi / 2) (tests check both).
 */
static double shortfall_pdf(const struct wall_detector_shortfall *c, double u_m)
{
  const double us = u_m * c->s;
  const double gauss_part = c->gauss_coef * exp(-u_m * u_m / c->two_r2);
  const double rayleigh_part = us / c->v3 * normal_cdf(us / c->rv) * exp(-u_m * u_m / c->two_v2);
  return gauss_part + rayleigh_part;
}

double wall_detector_shortfall_pdf(double u_m, double sonar_sigma_m, double ranging_sigma_m)
{
  const struct wall_detector_shortfall c = shortfall_of(sonar_sigma_m, ranging_sigma_m);
  return shortfall_pdf(&c, u_m);
}

/*
 * Survival function of the shortfall, P(u >= a): with F(a) = int_0^inf Rayleigh(x) Phi((a - x) / r) dx, an
 * integration by parts and the same completed square as above give
 *   P(u >= a) = 1 - Phi(a / r) + (s / v) exp(-a^2 / (2 v^2)) Phi(a s / (r v)).
 */
static double shortfall_sf(const struct wall_detector_shortfall *c, double a_m)
{
  return normal_cdf(-a_m / c->r) + c->s_over_v * exp(-a_m * a_m / c->two_v2) * normal_cdf(a_m * c->s / c->rv);
}

double wall_detector_shortfall_sf(double a_m, double sonar_sigma_m, double ranging_sigma_m)
{
  const struct wall_detector_shortfall c = shortfall_of(sonar_sigma_m, ranging_sigma_m);
  return shortfall_sf(&c, a_m);
}

/*
 * A wall at a uniform range w in [min, max] reads at most the minimum when w - (R - offset) <= min:
 * (1 / span) int_offset^inf P(R >= y) dy = s sqrt(2 pi) (1 - Phi(offset / s)) / span.
 */
static double clamped_wall_probability(const struct wall_detector_model *model, double span_m)
{
  const double s = model->sonar_sigma_m;
  return s / WALL_DETECTOR_INV_SQRT_2PI * normal_cdf(-model->sonar_offset_m / s) / span_m;
}

void wall_detector_model_terms_init(struct wall_detector_model_terms *terms, const struct wall_detector_model *model)
{
  const double s = model->sonar_sigma_m;
  const double r = model->ranging_sigma_m;
  const double span_m = model->sonar_max_m - model->sonar_min_m;
  const double crosstalk_sd_m = sqrt(0.25 * r * r + s * s);
  const float track_ratio_max = (float)(WALL_DETECTOR_INV_SQRT_2PI / model->track_sigma_m * span_m);
  *terms = (struct wall_detector_model_terms) {
    .model = *model,
    .shortfall = shortfall_of(s, r),
    .span_m = span_m,
    .crosstalk_sd_m = crosstalk_sd_m,
    .crosstalk_coef = WALL_DETECTOR_INV_SQRT_2PI / crosstalk_sd_m,
    .echo_prob = 1.0 - model->outlier_prob - model->crosstalk_prob,
    .clamped_wall_p = clamped_wall_probability(model, span_m),
    .track_ratio_max = track_ratio_max,
  };
}

double wall_detector_echo_part(const struct wall_detector_model_terms *terms, double shortfall_m)
{
  /* a reading inside the range: the shortfall's density against the wall's 1 / span */
  return terms->echo_prob * (shortfall_pdf(&terms->shortfall, shortfall_m) * terms->span_m);
}

double wall_detector_crosstalk_part(const struct wall_detector_model_terms *terms, double crosstalk_offset_m)
{
  const double z = crosstalk_offset_m / terms->crosstalk_sd_m;
  return terms->model.crosstalk_prob * (terms->crosstalk_coef * exp(-0.5 * z * z) * terms->span_m);
}

/**
 * The three parts of a copter echo's probability, each relative to a wall's (1 / span, or the clamped
 * probability): the echo (1 - eps - chi) r_echo, the cross-talk chi r_ct and the outlier eps.
 */
static void copter_parts(const struct wall_detector_model_terms *terms, float range_m, float peer_distance_m,
                         double part[WALL_DETECTOR_PART_NB])
{
  const struct wall_detector_model *model = &terms->model;
  /* echo: where the shortfall is 0; cross-talk: (path + c dt) / 2 with dt = 0, the path about the ranged distance */
  const double echo_m = (double)peer_distance_m - model->copter_offset_m + model->sonar_offset_m;
  const double crosstalk_m = 0.5 * peer_distance_m;
  if (!wall_detector_reading_clamped(model, range_m)) {
    part[WALL_DETECTOR_PART_ECHO] = wall_detector_echo_part(terms, echo_m - range_m);
    part[WALL_DETECTOR_PART_CROSSTALK] = wall_detector_crosstalk_part(terms, range_m - crosstalk_m);
  } else {
    /* a reading clamped to the minimum: probabilities of reading at most the minimum */
    const double echo_ratio = shortfall_sf(&terms->shortfall, echo_m - model->sonar_min_m) / terms->clamped_wall_p;
    const double crosstalk_ratio = normal_cdf((model->sonar_min_m - crosstalk_m) / terms->crosstalk_sd_m) /
                                   terms->clamped_wall_p;
    part[WALL_DETECTOR_PART_ECHO] = terms->echo_prob * echo_ratio;
    part[WALL_DETECTOR_PART_CROSSTALK] = model->crosstalk_prob * crosstalk_ratio;
  }
  /* the outlier part of a copter echo reads like a wall's: its ratio is 1 */
  part[WALL_DETECTOR_PART_OUTLIER] = model->outlier_prob;
}

float wall_detector_reading_llr(const struct wall_detector_model_terms *terms, float range_m, float peer_distance_m)
{
  double part[WALL_DETECTOR_PART_NB];
  copter_parts(terms, range_m, peer_distance_m, part);
  return (float)log(part[WALL_DETECTOR_PART_ECHO] + part[WALL_DETECTOR_PART_CROSSTALK] +
                    part[WALL_DETECTOR_PART_OUTLIER]);
}

enum wall_detector_part wall_detector_reading_part(const struct wall_detector_model_terms *terms, float range_m,
    float peer_distance_m)
{
  double part[WALL_DETECTOR_PART_NB];
  copter_parts(terms, range_m, peer_distance_m, part);
  enum wall_detector_part best = WALL_DETECTOR_PART_OUTLIER;
  if (part[WALL_DETECTOR_PART_CROSSTALK] > part[best]) {
    best = WALL_DETECTOR_PART_CROSSTALK;
  }
  if (part[WALL_DETECTOR_PART_ECHO] > part[best]) {
    best = WALL_DETECTOR_PART_ECHO;
  }
  return best;
}

/* in float (expf): the ratio's relative error is a few units of 6e-8 */
float wall_detector_track_ratio(const struct wall_detector_model_terms *terms, float range_m, float predicted_m,
                                float keep)
{
  const float z = (range_m - predicted_m) / terms->model.track_sigma_m;  // sd from the prediction
  float track_ratio;  // p(reading | the remembered wall) / p(reading | a wall at an unknown range)
  if (!wall_detector_reading_clamped(&terms->model, range_m)) {
    track_ratio = terms->track_ratio_max * expf(-0.5f * z * z);
  } else {
    track_ratio = (float)(normal_cdf(z) / terms->clamped_wall_p);
  }
  return keep * track_ratio + (1.f - keep);
}

float wall_detector_peer_prior(const struct wall_detector_model *model, float distance_m)
{
  const float radius_m = model->copter_radius_m;
  const float contact_m = 2.f * radius_m;
  return asinf(radius_m / fmaxf(distance_m, contact_m)) / (float)M_PI;
}

enum wall_detector_class wall_detector_baseline_class(const struct wall_detector_model *model, float range_m,
    const float *peer_distances_m, unsigned peer_nb, float eps_m)
{
  if (!wall_detector_is_echo(model, range_m)) {
    return WALL_DETECTOR_NO_ECHO;
  }
  for (unsigned i = 0; i < peer_nb; i++) {
    if (peer_distances_m[i] < model->ranging_max_m && fabsf(range_m - peer_distances_m[i]) < eps_m) {
      return WALL_DETECTOR_COPTER;
    }
  }
  return WALL_DETECTOR_WALL;
}
