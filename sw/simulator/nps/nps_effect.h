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
 * exists in closed form. Names and parameters follow ../shared/spec/discrepancy-report.md (glitch and bias_curve
 * are this library's own). Set-up from text, as model files write it: nps_effect_text.c.
 *
 * An effect maps the reading x (so far) to a new reading, given the true range, the context, the stream's
 * history and the caller's generator. x = +INFINITY means "no echo" (the chain's beyond_max decides what
 * the sensor reports); x = NaN means "no reading". Effects other than crosstalk, outlier and glitch pass a
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
 * | glitch         | with probability p: one of `values`, uniformly (2)      | p, values [m] (a list)      |
 * | bias_curve     | x + b(u), b linear between knots (at_i, b_i) (3)        | over, at, b [m] (lists)     |
 *
 * (1) default offset: the Rayleigh standard deviation sqrt((4 - pi) / 2) sigma (lab report 3.2).
 * (2) a reading that has nothing to do with the range (1 to 64 values, finite or +-inf, never NaN); it replaces
 *     any x, no echo and no reading too, and is final: a chain applies its glitches after its range limits
 *     (nps_sensor_chain_apply), so nothing clamps or changes it.
 * (3) u is the true range (over = "true_range") or a context column (over = "ctx_..."); 2 to 16 knots, at strictly
 *     increasing, b constant beyond the first and the last knot; a NaN u adds nothing.
 * Every effect with all-zero parameters is the identity, except scale (k is a ratio, its identity is 1).
 * Parameters are numbers except glitch `values` and bias_curve `over`, `at` and `b` (text parameters: a list of
 * numbers separated by white space, a column name), which only nps_effect_init_text takes.
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
  NPS_EFFECT_NLOS_BIAS, NPS_EFFECT_GMM, NPS_EFFECT_GLITCH, NPS_EFFECT_BIAS_CURVE,
  NPS_EFFECT_COUNT
};

#define NPS_EFFECT_MAX_PARAMS 2
/** Most text parameters of an effect (bias_curve: over, at, b). */
#define NPS_EFFECT_MAX_TEXT_PARAMS 3
/** Most values of a glitch; fewest and most knots of a bias_curve. */
#define NPS_GLITCH_MAX_VALUES 64
#define NPS_BIAS_CURVE_MIN_KNOTS 2
#define NPS_BIAS_CURVE_MAX_KNOTS 16

/** The b(u) of a bias_curve: linear between the knots (at[i], b_m[i]), constant beyond the first and the last. */
struct nps_bias_curve {
  char over[NPS_CTX_NAME_LEN];            /**< u: "true_range" or a ctx_ column */
  int over_slot;                          /**< -1: u is the true range; else u's context slot, which the model gives
                                               (nps_sensor_model_add_effect; NPS_CTX_SLOTS until then: u = 0) */
  size_t n_knots;
  double at[NPS_BIAS_CURVE_MAX_KNOTS];    /**< u at each knot, strictly increasing (u's unit) */
  double b_m[NPS_BIAS_CURVE_MAX_KNOTS];   /**< the bias at each knot [m] */
};

struct nps_effect {
  enum nps_effect_kind kind;
  double param[NPS_EFFECT_MAX_PARAMS]; /**< values in spec order (nps_effect_param_name) */
  const struct nps_gmm *gmm;           /**< the mixture of a gmm effect (not owned) */
  size_t n_values;                     /**< glitch: how many readings value_m holds */
  double value_m[NPS_GLITCH_MAX_VALUES]; /**< glitch: the readings it reports (finite or +-inf) [m] */
  struct nps_bias_curve curve;         /**< bias_curve */
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
/** Its text parameters (glitch: values; bias_curve: over, at, b), which nps_effect_param_* do not list. */
size_t nps_effect_text_param_count(int kind);
const char *nps_effect_text_param_name(int kind, size_t j);
/** Index of the text parameter called `name` of effect kind `kind`, or -1. */
int nps_effect_text_param_index(int kind, const char *name);
bool nps_effect_has_logpdf(int kind);

/**
 * Parse a number the way model files and defines write it: the whole text, finite.
 * @return 0, or -1 when the text is not one finite number
 */
int nps_effect_parse_number(const char *text, double *value);

/**
 * Set up an effect from its name and numeric parameters (unconditional, no mixture, no text parameter).
 * Missing parameters take their default (rayleigh_short offset, dropout p_per_m) or are an error.
 * @return 0, or -1 with the reason in err (unknown effect or parameter, missing or out-of-range value)
 */
int nps_effect_init(struct nps_effect *effect, const char *name, size_t n_params, const char *const key[],
                    const double value[], char *err, size_t err_len);

/**
 * Set up an effect from its name and parameters as model files write them: each a number
 * (nps_effect_parse_number), or a text parameter: a list of numbers separated by white space (glitch values:
 * finite or +-inf; bias_curve at and b: finite) or bias_curve's over ("true_range" or a ctx_ column, whose slot
 * the model gives).
 * @return 0, or -1 with the reason in err (as nps_effect_init; a bad list naming the bad value, a missing text
 *         parameter, too few or too many values or knots, at not strictly increasing, at and b of other lengths)
 */
int nps_effect_init_text(struct nps_effect *effect, const char *name, size_t n_params, const char *const key[],
                         const char *const text[], char *err, size_t err_len);

/** Index of the parameter called `name` of effect kind `kind`, or -1. */
int nps_effect_param_index(int kind, const char *name);
/** Change parameter j of an effect within its allowed interval; -1 (nothing changed) if j or value is invalid. */
int nps_effect_set_param(struct nps_effect *effect, size_t j, double value);

/** Introspection (bindings): kind, j-th parameter, condition's canonical text (NULL: none), mixture (NULL: none). */
int nps_effect_kind(const struct nps_effect *effect);
double nps_effect_param(const struct nps_effect *effect, size_t j);
const char *nps_effect_condition(const struct nps_effect *effect);
const struct nps_gmm *nps_effect_gmm(const struct nps_effect *effect);
/** A glitch's values [m], *n of them; NULL (n = 0) for any other effect. */
const double *nps_effect_glitch_values(const struct nps_effect *effect, size_t *n);
/** A bias_curve's u ("true_range" or a ctx_ column) and its *n knots (*at, *b_m [m]); NULL (n = 0) for others. */
const char *nps_effect_bias_curve(const struct nps_effect *effect, size_t *n, const double **at, const double **b_m);

/**
 * Whether an effect acts on a reading that is not finite (INFINITY: no echo within the maximum range): only
 * cross-talk, outliers and glitches make a reading from nothing; nps_effect_apply returns any other effect's input
 * then.
 */
static inline bool nps_effect_acts_on_no_echo(enum nps_effect_kind kind)
{
  return kind == NPS_EFFECT_CROSSTALK || kind == NPS_EFFECT_OUTLIER || kind == NPS_EFFECT_GLITCH;
}

/** Whether a chain applies an effect after its range limits, so that nothing clamps its reading: glitch. */
static inline bool nps_effect_is_final(enum nps_effect_kind kind)
{
  return kind == NPS_EFFECT_GLITCH;
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
