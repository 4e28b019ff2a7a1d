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
 * @file nps_effect.c
 * The sensor error effects: parameter tables, set-up, sampling and closed-form log-densities.
 */

#include "nps_effect.h"
#include "nps_error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_randist.h>

#include "nps_crosstalk.h"

/** Default rayleigh_short offset per sigma: the Rayleigh standard deviation sqrt((4 - pi) / 2) (report 3.2). */
#define NPS_EFFECT_RAYLEIGH_SD_PER_SIGMA sqrt((4.0 - M_PI) / 2.0)

struct param_spec {
  const char *name;
  double lo, hi;     /**< allowed closed interval */
  bool optional;     /**< has a default (see effect_defaults) */
};

struct effect_spec {
  const char *name;
  size_t n_params;
  struct param_spec param[NPS_EFFECT_MAX_PARAMS];
  bool has_logpdf;
  const char *text_param[NPS_EFFECT_MAX_TEXT_PARAMS];  /**< its text parameters (nps_effect_init_text), NULL-ended */
};

static const struct effect_spec specs[NPS_EFFECT_COUNT] = {
  [NPS_EFFECT_BIAS] = {"bias", 1, {{"b", -INFINITY, INFINITY, false}}, false, {NULL}},
  [NPS_EFFECT_SCALE] = {"scale", 1, {{"k", 0.0, INFINITY, false}}, false, {NULL}},
  [NPS_EFFECT_GAUSSIAN] = {"gaussian", 1, {{"sigma", 0.0, INFINITY, false}}, true, {NULL}},
  [NPS_EFFECT_RANGE_NOISE] = {
    "range_noise", 2, {{"sigma0", 0.0, INFINITY, false}, {"sigma1", 0.0, INFINITY, false}}, true, {NULL}
  },
  [NPS_EFFECT_RAYLEIGH_SHORT] = {
    "rayleigh_short", 2, {{"sigma", 0.0, INFINITY, false}, {"offset", -INFINITY, INFINITY, true}}, true, {NULL}
  },
  [NPS_EFFECT_CROSSTALK] = {"crosstalk", 1, {{"p", 0.0, 1.0, false}}, false, {NULL}},
  [NPS_EFFECT_DROPOUT] = {
    "dropout", 2, {{"p", 0.0, 1.0, false}, {"p_per_m", -INFINITY, INFINITY, true}}, false, {NULL}
  },
  [NPS_EFFECT_OUTLIER] = {"outlier", 1, {{"p", 0.0, 1.0, false}}, false, {NULL}},
  [NPS_EFFECT_QUANTIZATION] = {"quantization", 1, {{"step", 0.0, INFINITY, false}}, false, {NULL}},
  [NPS_EFFECT_LATENCY] = {"latency", 1, {{"tau", 0.0, INFINITY, false}}, false, {NULL}},
  [NPS_EFFECT_NLOS_BIAS] = {"nlos_bias", 1, {{"mean", 0.0, INFINITY, false}}, true, {NULL}},
  [NPS_EFFECT_GMM] = {"gmm", 0, {{NULL, 0, 0, false}}, true, {NULL}},
  [NPS_EFFECT_GLITCH] = {"glitch", 1, {{"p", 0.0, 1.0, false}}, false, {"values"}},
  [NPS_EFFECT_BIAS_CURVE] = {"bias_curve", 0, {{NULL, 0, 0, false}}, false, {"over", "at", "b"}},
};

static bool kind_ok(int kind)
{
  return kind >= 0 && kind < NPS_EFFECT_COUNT;
}

const char *nps_effect_name(int kind)
{
  return kind_ok(kind) ? specs[kind].name : NULL;
}

int nps_effect_kind_from_name(const char *name)
{
  for (int k = 0; name != NULL && k < NPS_EFFECT_COUNT; k++) {
    if (strcmp(name, specs[k].name) == 0) {
      return k;
    }
  }
  return -1;
}

size_t nps_effect_param_count(int kind)
{
  return kind_ok(kind) ? specs[kind].n_params : 0;
}

const char *nps_effect_param_name(int kind, size_t j)
{
  return (kind_ok(kind) && j < specs[kind].n_params) ? specs[kind].param[j].name : NULL;
}

size_t nps_effect_text_param_count(int kind)
{
  size_t n = 0;
  while (kind_ok(kind) && n < NPS_EFFECT_MAX_TEXT_PARAMS && specs[kind].text_param[n] != NULL) {
    n++;
  }
  return n;
}

const char *nps_effect_text_param_name(int kind, size_t j)
{
  return j < nps_effect_text_param_count(kind) ? specs[kind].text_param[j] : NULL;
}

int nps_effect_text_param_index(int kind, const char *name)
{
  for (size_t j = 0; j < nps_effect_text_param_count(kind); j++) {
    if (strcmp(name, specs[kind].text_param[j]) == 0) {
      return (int)j;
    }
  }
  return -1;
}

bool nps_effect_has_logpdf(int kind)
{
  return kind_ok(kind) && specs[kind].has_logpdf;
}

/** The list of a kind's parameter names, for error messages. */
static void param_list(int kind, char *buf, size_t len)
{
  buf[0] = '\0';
  for (size_t j = 0; j < specs[kind].n_params + nps_effect_text_param_count(kind); j++) {
    size_t used = strlen(buf);
    snprintf(buf + used, len - used, "%s%s", j ? ", " : "",
             j < specs[kind].n_params ? specs[kind].param[j].name : specs[kind].text_param[j - specs[kind].n_params]);
  }
  if (buf[0] == '\0') {
    snprintf(buf, len, "none");
  }
}

int nps_effect_param_index(int kind, const char *name)
{
  for (size_t j = 0; kind_ok(kind) && j < specs[kind].n_params; j++) {
    if (strcmp(name, specs[kind].param[j].name) == 0) {
      return (int)j;
    }
  }
  return -1;
}

int nps_effect_set_param(struct nps_effect *effect, size_t j, double value)
{
  const struct effect_spec *spec = &specs[effect->kind];
  if (j >= spec->n_params || !(value >= spec->param[j].lo && value <= spec->param[j].hi)) {
    return -1;
  }
  effect->param[j] = value;
  return 0;
}

int nps_effect_init(struct nps_effect *effect, const char *name, size_t n_params, const char *const key[],
                    const double value[], char *err, size_t err_len)
{
  int kind = nps_effect_kind_from_name(name);
  if (kind < 0) {
    char known[256] = "";
    for (int k = 0; k < NPS_EFFECT_COUNT; k++) {
      size_t used = strlen(known);
      snprintf(known + used, sizeof(known) - used, "%s%s", k ? ", " : "", specs[k].name);
    }
    nps_error_set(err, err_len, "unknown effect '%s' (known: %s)", name ? name : "", known);
    return -1;
  }
  const struct effect_spec *spec = &specs[kind];
  bool given[NPS_EFFECT_MAX_PARAMS] = {false};
  memset(effect, 0, sizeof(*effect));
  effect->kind = (enum nps_effect_kind)kind;
  for (size_t i = 0; i < n_params; i++) {
    const int found = nps_effect_param_index(kind, key[i]);
    const size_t j = found < 0 ? spec->n_params : (size_t)found;
    if (found < 0 && nps_effect_text_param_index(kind, key[i]) >= 0) {
      nps_error_set(err, err_len, "parameter '%s' of effect '%s' is text (nps_effect_init_text)", key[i], name);
      return -1;
    }
    if (found < 0) {
      char expected[128];
      param_list(kind, expected, sizeof(expected));
      nps_error_set(err, err_len, "unknown parameter '%s' for effect '%s' (expected: %s)", key[i], name, expected);
      return -1;
    }
    if (given[j]) {
      nps_error_set(err, err_len, "parameter '%s' of effect '%s' given twice", key[i], name);
      return -1;
    }
    if (!(value[i] >= spec->param[j].lo && value[i] <= spec->param[j].hi)) {
      nps_error_set(err, err_len, "%s %s = %g is outside [%g, %g]", name, key[i], value[i], spec->param[j].lo,
              spec->param[j].hi);
      return -1;
    }
    given[j] = true;
    effect->param[j] = value[i];
  }
  for (size_t j = 0; j < spec->n_params; j++) {
    if (!given[j] && !spec->param[j].optional) {
      nps_error_set(err, err_len, "effect '%s' needs parameter '%s'", name, spec->param[j].name);
      return -1;
    }
  }
  if (kind == NPS_EFFECT_RAYLEIGH_SHORT && !given[1]) {
    effect->param[1] = NPS_EFFECT_RAYLEIGH_SD_PER_SIGMA * effect->param[0];
  }
  return 0;
}

int nps_effect_kind(const struct nps_effect *effect)
{
  return (int)effect->kind;
}

double nps_effect_param(const struct nps_effect *effect, size_t j)
{
  return j < NPS_EFFECT_MAX_PARAMS ? effect->param[j] : NAN;
}

const char *nps_effect_condition(const struct nps_effect *effect)
{
  return effect->condition.n_terms > 0 ? effect->condition.text : NULL;
}

const struct nps_gmm *nps_effect_gmm(const struct nps_effect *effect)
{
  return effect->gmm;
}

const double *nps_effect_glitch_values(const struct nps_effect *effect, size_t *n)
{
  const bool glitch = effect->kind == NPS_EFFECT_GLITCH;
  *n = glitch ? effect->n_values : 0;
  return glitch ? effect->value_m : NULL;
}

const char *nps_effect_bias_curve(const struct nps_effect *effect, size_t *n, const double **at, const double **b_m)
{
  const bool curve = effect->kind == NPS_EFFECT_BIAS_CURVE;
  *n = curve ? effect->curve.n_knots : 0;
  *at = curve ? effect->curve.at : NULL;
  *b_m = curve ? effect->curve.b_m : NULL;
  return curve ? effect->curve.over : NULL;
}

static double crosstalk(const struct nps_effect *effect, const struct nps_effect_env *env, double x_m, gsl_rng *r)
{
  const struct nps_sensor_ctx *ctx = env->ctx;
  if (ctx == NULL || !(ctx->facing_sonars > 0.0) || !(gsl_rng_uniform(r) < effect->param[0])) {
    return x_m;
  }
  double path_m = ctx->crosstalk_path_m > 0.0 ? ctx->crosstalk_path_m : env->true_range_m;
  double offset_s = isnan(ctx->trigger_offset_s) ? 0.0 : ctx->trigger_offset_s;
  /* a sonar reports the first echo: the foreign pulse only shows if it arrives before the sensor's own echo */
  return fmin(x_m, nps_crosstalk_reading_m(path_m, offset_s, env->speed_of_sound_mps));
}

static double latency(const struct nps_effect *effect, const struct nps_effect_env *env, double x_m)
{
  if (env->state == NULL || effect->param[0] == 0.0) {
    return x_m;
  }
  double then_m = nps_sensor_state_true_range_at(env->state, env->t_s - effect->param[0]);
  return x_m + (then_m - env->true_range_m);
}

static double glitch(const struct nps_effect *effect, double x_m, gsl_rng *r)
{
  if (effect->n_values == 0) {
    return x_m;
  }
  /* both numbers are drawn for every reading, as for outliers: the rest of the stream does not depend on p */
  const bool fires = gsl_rng_uniform(r) < effect->param[0];
  const double value_m = effect->value_m[gsl_rng_uniform_int(r, effect->n_values)];
  return fires ? value_m : x_m;
}

/** b(u) [m]: linear between the knots, constant beyond the first and the last; 0 for a NaN u or no knots. */
static double bias_curve_m(const struct nps_bias_curve *c, double u)
{
  if (c->n_knots == 0 || isnan(u)) {
    return 0.0;
  }
  if (u <= c->at[0]) {
    return c->b_m[0];
  }
  size_t i = 1;
  while (i < c->n_knots && u >= c->at[i]) {
    i++;
  }
  if (i == c->n_knots) {
    return c->b_m[i - 1];
  }
  /* at[i - 1] <= u < at[i]: at a knot f = 0, so the knot's own b exactly */
  const double f = (u - c->at[i - 1]) / (c->at[i] - c->at[i - 1]);
  return c->b_m[i - 1] + f * (c->b_m[i] - c->b_m[i - 1]);
}

static double bias_curve(const struct nps_effect *effect, const struct nps_effect_env *env, double x_m)
{
  const struct nps_bias_curve *c = &effect->curve;
  return x_m + bias_curve_m(c, c->over_slot < 0 ? env->true_range_m : nps_sensor_ctx_get(env->ctx, c->over_slot));
}

double nps_effect_apply(const struct nps_effect *effect, const struct nps_effect_env *env, double x_m, gsl_rng *r)
{
  const double *p = effect->param;
  if (!nps_condition_holds(&effect->condition, env->ctx)) {
    return x_m;
  }
  if (!isfinite(x_m) && !nps_effect_acts_on_no_echo(effect->kind)) {
    return x_m;
  }
  switch (effect->kind) {
    case NPS_EFFECT_BIAS:
      return x_m + p[0];
    case NPS_EFFECT_SCALE:
      return p[0] * x_m;
    case NPS_EFFECT_GAUSSIAN:
      return x_m + gsl_ran_gaussian_ziggurat(r, p[0]);
    case NPS_EFFECT_RANGE_NOISE:
      return x_m + gsl_ran_gaussian_ziggurat(r, p[0] + p[1] * fabs(x_m));
    case NPS_EFFECT_RAYLEIGH_SHORT:
      return x_m - (gsl_ran_rayleigh(r, p[0]) - p[1]);
    case NPS_EFFECT_CROSSTALK:
      return crosstalk(effect, env, x_m, r);
    case NPS_EFFECT_DROPOUT:
      return gsl_rng_uniform(r) < p[0] + p[1] * env->true_range_m ? INFINITY : x_m;
    case NPS_EFFECT_OUTLIER: {
      /* both numbers are drawn for every reading, so the rest of the stream does not depend on p: a fit of p
         with fixed seeds (common random numbers) sees only the readings p changes */
      bool fires = gsl_rng_uniform(r) < p[0];
      double outlier_m = gsl_ran_flat(r, env->min_range_m, env->max_range_m);
      return fires ? outlier_m : x_m;
    }
    case NPS_EFFECT_QUANTIZATION:
      return p[0] > 0.0 ? p[0] * round(x_m / p[0]) : x_m;
    case NPS_EFFECT_LATENCY:
      return latency(effect, env, x_m);
    case NPS_EFFECT_NLOS_BIAS:
      return x_m + gsl_ran_exponential(r, p[0]);
    case NPS_EFFECT_GMM:
      return nps_gmm_sample(effect->gmm, x_m, r);
    case NPS_EFFECT_GLITCH:
      return glitch(effect, x_m, r);
    case NPS_EFFECT_BIAS_CURVE:
      return bias_curve(effect, env, x_m);
    default:
      return NAN;
  }
}

/** log N(d; 0, sigma^2); a point mass at 0 for sigma = 0 (+inf there, -inf elsewhere). */
static double log_normal(double d, double sigma)
{
  if (sigma == 0.0) {
    return d == 0.0 ? INFINITY : -INFINITY;
  }
  return -0.5 * (d / sigma) * (d / sigma) - log(sigma) - 0.5 * log(2.0 * M_PI);
}

double nps_effect_logpdf(const struct nps_effect *effect, double x_in_m, double x_out_m)
{
  const double *p = effect->param;
  switch (effect->kind) {
    case NPS_EFFECT_GAUSSIAN:
      return log_normal(x_out_m - x_in_m, p[0]);
    case NPS_EFFECT_RANGE_NOISE:
      return log_normal(x_out_m - x_in_m, p[0] + p[1] * fabs(x_in_m));
    case NPS_EFFECT_RAYLEIGH_SHORT: {
      /* R = x_in - x_out + offset ~ Rayleigh(sigma): log(R / sigma^2) - R^2 / (2 sigma^2), R > 0 */
      double rr = x_in_m - x_out_m + p[1];
      if (p[0] == 0.0) {
        return rr == 0.0 ? INFINITY : -INFINITY;
      }
      return rr > 0.0 ? log(rr / (p[0] * p[0])) - 0.5 * (rr / p[0]) * (rr / p[0]) : -INFINITY;
    }
    case NPS_EFFECT_NLOS_BIAS: {
      /* E = x_out - x_in ~ Exponential(mean): -log(mean) - E / mean, E >= 0 */
      double e = x_out_m - x_in_m;
      if (p[0] == 0.0) {
        return e == 0.0 ? INFINITY : -INFINITY;
      }
      return e >= 0.0 ? -log(p[0]) - e / p[0] : -INFINITY;
    }
    case NPS_EFFECT_GMM:
      return nps_gmm_conditional_logpdf(effect->gmm, x_in_m, x_out_m);
    default:
      return NAN;
  }
}

int nps_effect_logpdf_named(const char *name, size_t n_params, const char *const key[], const double value[],
                            size_t n, const double *x_in_m, const double *x_out_m, double *logpdf,
                            char *err, size_t err_len)
{
  struct nps_effect effect;
  if (nps_effect_init(&effect, name, n_params, key, value, err, err_len) != 0) {
    return -1;
  }
  if (!specs[effect.kind].has_logpdf || effect.kind == NPS_EFFECT_GMM) {
    nps_error_set(err, err_len, "effect '%s' has no closed-form log-density%s", name,
            effect.kind == NPS_EFFECT_GMM ? " by name (use the mixture: nps_gmm_conditional_logpdf)" : "");
    return -1;
  }
  for (size_t i = 0; i < n; i++) {
    logpdf[i] = nps_effect_logpdf(&effect, x_in_m[i], x_out_m[i]);
  }
  return 0;
}
