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
 * @file nps_effect.h
 * The sensor error effects library: what each effect does to one reading, and its log-density where one
 * exists in closed form. Names and parameters follow ../shared/spec/discrepancy-report.md.
 *
 * An effect maps the reading x (so far) to a new reading, given the true range, the context, the stream's
 * history and the caller's generator. x = +INFINITY means "no echo" (the chain's beyond_max decides what
 * the sensor reports); x = NaN means "no reading". Effects other than crosstalk and outlier pass a
 * non-finite x through unchanged.
 *
 * | effect         | output                                                  | parameters (spec order)     |
 * |----------------|---------------------------------------------------------|-----------------------------|
 * | bias           | x + b                                                   | b [m]                       |
 * | scale          | k x                                                     | k [-] (identity: k = 1)     |
 * | gaussian       | x + N(0, sigma^2)                                       | sigma [m]                   |
 * | range_noise    | x + N(0, (sigma0 + sigma1 abs(x))^2)                    | sigma0 [m], sigma1 [m/m]    |
 * | rayleigh_short | x - (R - offset), R ~ Rayleigh(sigma)                   | sigma [m], offset [m] (1)   |
 * | crosstalk      | with probability p, if a sonar faces this one: the first| p                           |
 * |                | echo, min(x, (path + c trigger_offset) / 2) (crosstalk.h)|                             |
 * | dropout        | with probability p + p_per_m * true: no echo (+inf)     | p, p_per_m [1/m] (default 0)|
 * | outlier        | with probability p: U(min_range, max_range)             | p                           |
 * | quantization   | step * round(x / step)                                  | step [m]                    |
 * | latency        | x + true(t - tau) - true(t) (true range tau earlier)    | tau [s]                     |
 * | nlos_bias      | x + Exponential(mean)                                   | mean [m]                    |
 * | gmm            | a draw of p(measured given true = x) (nps_gmm.h)        | (the mixture)               |
 *
 * (1) default offset: the Rayleigh standard deviation sqrt((4 - pi) / 2) sigma (lab report 3.2).
 * Every effect with all-zero parameters is the identity, except scale (k is a ratio, its identity is 1).
 */

#ifndef NPS_EFFECT_H
#define NPS_EFFECT_H

#include <stdbool.h>
#include <stddef.h>
#include <gsl/gsl_rng.h>

#include "nps_condition.h"
#include "nps_gmm.h"
#include "nps_sensor_model_ctx.h"

enum nps_effect_kind {
  NPS_EFFECT_BIAS, NPS_EFFECT_SCALE, NPS_EFFECT_GAUSSIAN, NPS_EFFECT_RANGE_NOISE, NPS_EFFECT_RAYLEIGH_SHORT,
  NPS_EFFECT_CROSSTALK, NPS_EFFECT_DROPOUT, NPS_EFFECT_OUTLIER, NPS_EFFECT_QUANTIZATION, NPS_EFFECT_LATENCY,
  NPS_EFFECT_NLOS_BIAS, NPS_EFFECT_GMM,
  NPS_EFFECT_COUNT
};

#define NPS_EFFECT_MAX_PARAMS 2

struct nps_effect {
  enum nps_effect_kind kind;
  double param[NPS_EFFECT_MAX_PARAMS]; /**< values in spec order (nps_effect_param_name) */
  const struct nps_gmm *gmm;           /**< the mixture of a gmm effect (not owned) */
  struct nps_condition condition;      /**< where it applies (nps_condition.h; no terms: always) */
};

/** Everything an effect may read besides x. */
struct nps_effect_env {
  double t_s;                              /**< time of the reading [s] */
  double true_range_m;                     /**< true range [m] */
  const struct nps_sensor_ctx *ctx;        /**< context (NULL: all zero) */
  const struct nps_sensor_state *state;    /**< stream history, newest entry = this reading (NULL: no latency) */
  double min_range_m, max_range_m;         /**< the sensor's range [m] (outlier) */
  double speed_of_sound_mps;               /**< [m/s] (crosstalk) */
};

/** Library tables (for bindings and error messages). */
const char *nps_effect_name(int kind);
/** The kind of an effect name, or -1. */
int nps_effect_kind_from_name(const char *name);
size_t nps_effect_param_count(int kind);
const char *nps_effect_param_name(int kind, size_t j);
bool nps_effect_has_logpdf(int kind);

/**
 * Parse a number the way model files and defines write it: the whole text, finite.
 * @return 0, or -1 when the text is not one finite number
 */
int nps_effect_parse_number(const char *text, double *value);

/**
 * Set up an effect from its name and parameters (unconditional, no mixture).
 * Missing parameters take their default (rayleigh_short offset, dropout p_per_m) or are an error.
 * @return 0, or -1 with the reason in err (unknown effect or parameter, missing or out-of-range value)
 */
int nps_effect_init(struct nps_effect *effect, const char *name, size_t n_params, const char *const key[],
                    const double value[], char *err, size_t err_len);

/** Index of the parameter called `name` of effect kind `kind`, or -1. */
int nps_effect_param_index(int kind, const char *name);
/** Change parameter j of an effect within its allowed interval; -1 (nothing changed) if j or value is invalid. */
int nps_effect_set_param(struct nps_effect *effect, size_t j, double value);

/** Introspection (bindings): kind, j-th parameter, condition's canonical text (NULL: none), mixture (NULL: none). */
int nps_effect_kind(const struct nps_effect *effect);
double nps_effect_param(const struct nps_effect *effect, size_t j);
const char *nps_effect_condition(const struct nps_effect *effect);
const struct nps_gmm *nps_effect_gmm(const struct nps_effect *effect);

/**
 * Whether an effect acts on a reading that is not finite (INFINITY: no echo within the maximum range): only
 * cross-talk and outliers make a reading from nothing; nps_effect_apply returns any other effect's input then.
 */
static inline bool nps_effect_acts_on_no_echo(enum nps_effect_kind kind)
{
  return kind == NPS_EFFECT_CROSSTALK || kind == NPS_EFFECT_OUTLIER;
}

/** The new reading (see the table above); draws from r only when needed. */
double nps_effect_apply(const struct nps_effect *effect, const struct nps_effect_env *env, double x_m, gsl_rng *r);

/** log density of output x_out given input x_in [log 1/m]; NaN for effects without a closed form. */
double nps_effect_logpdf(const struct nps_effect *effect, double x_in_m, double x_out_m);

/**
 * nps_effect_logpdf for n pairs of an effect given by name and parameters (bindings; gmm: use nps_gmm).
 * @return 0, or -1 with the reason in err (as nps_effect_init, or no closed form)
 */
int nps_effect_logpdf_named(const char *name, size_t n_params, const char *const key[], const double value[],
                            size_t n, const double *x_in_m, const double *x_out_m, double *logpdf,
                            char *err, size_t err_len);

#endif /* NPS_EFFECT_H */
