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
 * @file nps_sensor_model.c
 * Sensor-model chains: building, applying to one reading, log replay of many streams, introspection.
 */

#include "nps_sensor_model.h"
#include "nps_error.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nps_crosstalk.h"
#include "nps_rng.h"

/** Default limits per kind: sonar [0.2, 3.0] m (lab report 3.2), ranging [0, 2.5] m (report 4.1). */
static const double default_min_range_m[NPS_SENSOR_KINDS] = {0.2, 0.0};
static const double default_max_range_m[NPS_SENSOR_KINDS] = {3.0, 2.5};
static const char *const kind_names[NPS_SENSOR_KINDS] = {"sonar", "ranging"};

int nps_sensor_kind_from_name(const char *name)
{
  for (int k = 0; name != NULL && k < NPS_SENSOR_KINDS; k++) {
    if (strcmp(name, kind_names[k]) == 0) {
      return k;
    }
  }
  return -1;
}

struct nps_sensor_model *nps_sensor_model_new(void)
{
  return calloc(1, sizeof(struct nps_sensor_model));
}

void nps_sensor_model_free(struct nps_sensor_model *model)
{
  if (model == NULL) {
    return;
  }
  for (size_t i = 0; i < model->n_gmm; i++) {
    nps_gmm_free(model->gmm[i]);
  }
  free(model->name);
  free(model);
}

const char *nps_sensor_model_name(const struct nps_sensor_model *model)
{
  return model->name;
}

static int parse_attr_number(const char *what, const char *key, const char *text, double *value,
                             char *err, size_t err_len)
{
  if (nps_effect_parse_number(text, value) != 0) {
    nps_error_set(err, err_len, "%s '%s' = '%s' is not a finite number", what, key, text ? text : "");
    return -1;
  }
  return 0;
}

int nps_sensor_model_add_chain(struct nps_sensor_model *model, const char *kind, size_t n_attrs,
                               const char *const key[], const char *const value[], char *err, size_t err_len)
{
  int k = nps_sensor_kind_from_name(kind);
  if (k < 0) {
    nps_error_set(err, err_len, "unknown sensor '%s' (expected sonar or ranging)", kind ? kind : "");
    return -1;
  }
  if (model->has_chain[k]) {
    nps_error_set(err, err_len, "the %s chain is defined twice", kind);
    return -1;
  }
  struct nps_sensor_chain chain = {
    .kind = (enum nps_sensor_kind)k,
    .min_range_m = default_min_range_m[k],
    .max_range_m = default_max_range_m[k],
    .beyond_max = NPS_BEYOND_MAX_REPORT_MAX,
    .speed_of_sound_mps = NPS_CROSSTALK_SPEED_OF_SOUND_MPS,
  };
  for (size_t i = 0; i < n_attrs; i++) {
    int rc = 0;
    if (strcmp(key[i], "min_range") == 0) {
      rc = parse_attr_number(kind, key[i], value[i], &chain.min_range_m, err, err_len);
    } else if (strcmp(key[i], "max_range") == 0) {
      rc = parse_attr_number(kind, key[i], value[i], &chain.max_range_m, err, err_len);
    } else if (strcmp(key[i], "speed_of_sound") == 0) {
      rc = parse_attr_number(kind, key[i], value[i], &chain.speed_of_sound_mps, err, err_len);
    } else if (strcmp(key[i], "beyond_max") == 0) {
      if (strcmp(value[i], "max") == 0) {
        chain.beyond_max = NPS_BEYOND_MAX_REPORT_MAX;
      } else if (strcmp(value[i], "none") == 0) {
        chain.beyond_max = NPS_BEYOND_MAX_NO_READING;
      } else {
        nps_error_set(err, err_len, "%s beyond_max = '%s' (expected 'max' or 'none')", kind, value[i]);
        rc = -1;
      }
    } else {
      nps_error_set(err, err_len, "unknown %s attribute '%s' (expected min_range, max_range, beyond_max, "
              "speed_of_sound)", kind, key[i]);
      rc = -1;
    }
    if (rc != 0) {
      return -1;
    }
  }
  if (!(chain.min_range_m >= 0.0 && chain.max_range_m > chain.min_range_m)) {
    nps_error_set(err, err_len, "%s range [%g, %g] m: need 0 <= min_range < max_range", kind, chain.min_range_m,
            chain.max_range_m);
    return -1;
  }
  if (!(chain.speed_of_sound_mps > 0.0)) {
    nps_error_set(err, err_len, "%s speed_of_sound = %g m/s: must be > 0", kind, chain.speed_of_sound_mps);
    return -1;
  }
  model->chain[k] = chain;
  model->has_chain[k] = true;
  return 0;
}

/** A condition must name range-log context columns: "ctx_" followed by [a-z0-9_] (its parser bounds the length). */
static bool valid_ctx_name(const char *name)
{
  size_t n = strlen(name);
  if (n <= 4 || strncmp(name, "ctx_", 4) != 0) {
    return false;
  }
  for (size_t i = 4; i < n; i++) {
    if (!(islower((unsigned char)name[i]) || isdigit((unsigned char)name[i]) || name[i] == '_')) {
      return false;
    }
  }
  return true;
}

int nps_sensor_model_ctx_slot(const struct nps_sensor_model *model, const char *column)
{
  for (int s = 0; column != NULL && s < NPS_CTX_EXTRA0; s++) {
    if (strcmp(column, nps_sensor_ctx_fixed_name(s)) == 0) {
      return s;
    }
  }
  for (size_t i = 0; column != NULL && i < model->n_ctx_extra; i++) {
    if (strcmp(column, model->ctx_extra[i]) == 0) {
      return NPS_CTX_EXTRA0 + (int)i;
    }
  }
  return -1;
}

const char *nps_sensor_model_ctx_slot_name(const struct nps_sensor_model *model, int slot)
{
  if (slot >= 0 && slot < NPS_CTX_EXTRA0) {
    return nps_sensor_ctx_fixed_name(slot);
  }
  size_t i = (size_t)(slot - NPS_CTX_EXTRA0);
  return (slot >= NPS_CTX_EXTRA0 && i < model->n_ctx_extra) ? model->ctx_extra[i] : NULL;
}

/** "a, b, c" into out: the names, cut short with "..." when out is full. */
static void list_names(char *out, size_t out_len, size_t n, const char *const name[])
{
  size_t used = 0;
  out[0] = '\0';
  for (size_t i = 0; i < n && used < out_len; i++) {
    int w = snprintf(out + used, out_len - used, "%s%s", i ? ", " : "", name[i]);
    used += w > 0 ? (size_t)w : 0;
  }
  if (used >= out_len && out_len > 4) {
    strcpy(out + out_len - 4, "...");
  }
}

/** nps_sensor_model_check_column of a column named by `what` ("condition", "bias_curve over") in the message. */
static int check_column_of(const char *what, const char *column, size_t n_log_columns, const char *const log_column[],
                           char *err, size_t err_len)
{
  const char *simulator[NPS_CTX_EXTRA0];
  for (int s = 0; s < NPS_CTX_EXTRA0; s++) {
    simulator[s] = nps_sensor_ctx_fixed_name(s);
    if (strcmp(column, simulator[s]) == 0) {
      return 0;
    }
  }
  for (size_t i = 0; i < n_log_columns; i++) {
    if (strcmp(column, log_column[i]) == 0) {
      return 0;
    }
  }
  char known[NPS_SENSOR_MODEL_ERR_LEN / 2], of_log[NPS_SENSOR_MODEL_ERR_LEN / 4];
  list_names(known, sizeof(known), NPS_CTX_EXTRA0, simulator);
  list_names(of_log, sizeof(of_log), n_log_columns, log_column);
  nps_error_set(err, err_len, "%s '%s': unknown context column (the simulator has %s%s%s)", what, column, known,
                n_log_columns ? "; the log has " : "", of_log);
  return -1;
}

int nps_sensor_model_check_column(const char *column, size_t n_log_columns, const char *const log_column[],
                                  char *err, size_t err_len)
{
  return check_column_of("condition", column, n_log_columns, log_column, err, err_len);
}

int nps_sensor_model_check_effect_columns(const struct nps_effect *effect, size_t n_log_columns,
                                          const char *const log_column[], bool *in_condition,
                                          char *err, size_t err_len)
{
  const struct nps_condition *c = &effect->condition;
  const struct nps_bias_curve *curve = &effect->curve;
  int rc = 0;
  for (size_t t = 0; rc == 0 && t < c->n_terms; t++) {
    rc = check_column_of("condition", c->term[t].column, n_log_columns, log_column, err, err_len);
  }
  if (in_condition != NULL) {
    *in_condition = rc != 0;
  }
  if (rc == 0 && effect->kind == NPS_EFFECT_BIAS_CURVE && curve->over_slot >= 0) {
    rc = check_column_of("bias_curve over", curve->over, n_log_columns, log_column, err, err_len);
  }
  return rc;
}

/** The slot of a column named by `what` (a condition, a bias curve), adding a model-defined slot when needed; -1
 * with err when it is no context column or the slots are full. */
static int column_slot(struct nps_sensor_model *model, const char *what, const char *column, char *err, size_t err_len)
{
  if (!valid_ctx_name(column)) {
    nps_error_set(err, err_len, "%s '%s' is not a context column (expected %sctx_ followed by a-z, 0-9, _)", what,
                  column, strcmp(what, "condition") == 0 ? "" : "true_range or ");
    return -1;
  }
  int slot = nps_sensor_model_ctx_slot(model, column);
  if (slot >= 0) {
    return slot;
  }
  if (model->n_ctx_extra == NPS_CTX_EXTRA_MAX) {
    nps_error_set(err, err_len, "%s '%s': a model may name at most %d context columns besides the fixed ones", what,
                  column, NPS_CTX_EXTRA_MAX);
    return -1;
  }
  snprintf(model->ctx_extra[model->n_ctx_extra], NPS_CTX_NAME_LEN, "%s", column);
  return NPS_CTX_EXTRA0 + (int)model->n_ctx_extra++;
}

/** The slots of every column an effect names: its condition's, a bias curve's (model-defined slots added on error
 * are given back). */
static int effect_slots(struct nps_sensor_model *model, struct nps_effect *effect, char *err, size_t err_len)
{
  const size_t n_ctx_extra = model->n_ctx_extra;
  struct nps_condition *cond = &effect->condition;
  struct nps_bias_curve *curve = &effect->curve;
  int slot = 0;
  for (size_t t = 0; slot >= 0 && t < cond->n_terms; t++) {
    slot = cond->term[t].slot = column_slot(model, "condition", cond->term[t].column, err, err_len);
  }
  if (slot >= 0 && effect->kind == NPS_EFFECT_BIAS_CURVE && curve->over_slot >= 0) {
    slot = curve->over_slot = column_slot(model, "bias_curve over", curve->over, err, err_len);
  }
  if (slot < 0) {
    model->n_ctx_extra = n_ctx_extra;
    return -1;
  }
  return 0;
}

int nps_sensor_model_add_effect(struct nps_sensor_model *model, const char *kind, const char *name,
                                size_t n_params, const char *const key[], const char *const value[],
                                const struct nps_condition *condition, struct nps_gmm *gmm, char *err, size_t err_len)
{
  int k = nps_sensor_kind_from_name(kind);
  struct nps_sensor_chain *chain = k >= 0 && model->has_chain[k] ? &model->chain[k] : NULL;
  struct nps_effect effect;
  int rc = -1;
  if (chain == NULL) {
    nps_error_set(err, err_len, "effect '%s' for sensor '%s', which has no chain", name, kind ? kind : "");
  } else if (chain->n_effects == NPS_SENSOR_CHAIN_MAX_EFFECTS) {
    nps_error_set(err, err_len, "the %s chain has more than %d effects", kind, NPS_SENSOR_CHAIN_MAX_EFFECTS);
  } else {
    rc = nps_effect_init_text(&effect, name, n_params, key, value, err, err_len);
  }
  if (rc == 0 && (effect.kind == NPS_EFFECT_GMM) != (gmm != NULL)) {
    nps_error_set(err, err_len, gmm ? "effect '%s' takes no mixture" : "effect '%s' needs a mixture", name);
    rc = -1;
  }
  if (rc == 0) {
    if (condition != NULL) {
      effect.condition = *condition;
    }
    rc = effect_slots(model, &effect, err, err_len);
  }
  if (rc != 0) {
    nps_gmm_free(gmm);
    return -1;
  }
  if (gmm != NULL) {
    model->gmm[model->n_gmm++] = gmm;
    effect.gmm = gmm;
  }
  chain->effect[chain->n_effects++] = effect;
  chain->reads_state = chain->reads_state || effect.kind == NPS_EFFECT_LATENCY;
  chain->has_final = chain->has_final || nps_effect_is_final(effect.kind);
  return 0;
}

const struct nps_sensor_chain *nps_sensor_model_chain_of(const struct nps_sensor_model *model,
    enum nps_sensor_kind kind)
{
  return model->has_chain[kind] ? &model->chain[kind] : NULL;
}

const struct nps_sensor_chain *nps_sensor_model_chain(const struct nps_sensor_model *model, const char *kind)
{
  int k = nps_sensor_kind_from_name(kind);
  return k >= 0 ? nps_sensor_model_chain_of(model, (enum nps_sensor_kind)k) : NULL;
}

bool nps_sensor_chain_reads_state(const struct nps_sensor_chain *chain)
{
  return chain->reads_state;
}

double nps_sensor_chain_limit(const struct nps_sensor_chain *chain, double x_m)
{
  if (isnan(x_m)) {
    return NAN;
  }
  if (x_m == INFINITY) {
    return chain->beyond_max == NPS_BEYOND_MAX_REPORT_MAX ? chain->max_range_m : NAN;
  }
  /* fmin(fmax(x, min), max) for a number x and limits that are numbers (checked at load), as comparisons:
   * the libm calls are not inlined; the ties keep the limit, as fmax and fmin do on x86-64 (maxsd, minsd) */
  const double raised_m = x_m > chain->min_range_m ? x_m : chain->min_range_m;
  return raised_m < chain->max_range_m ? raised_m : chain->max_range_m;
}

double nps_sensor_chain_apply(const struct nps_sensor_chain *chain, double t_s, double true_range_m,
                              const struct nps_sensor_ctx *ctx, struct nps_sensor_state *state, gsl_rng *r)
{
  if (state != NULL) {
    nps_sensor_state_push(state, t_s, true_range_m);
  }
  struct nps_effect_env env = {
    .t_s = t_s,
    .true_range_m = true_range_m,
    .ctx = ctx,
    .state = state,
    .min_range_m = chain->min_range_m,
    .max_range_m = chain->max_range_m,
    .speed_of_sound_mps = chain->speed_of_sound_mps,
  };
  double x_m = true_range_m > chain->max_range_m ? INFINITY : true_range_m;
  for (size_t i = 0; i < chain->n_effects; i++) {
    if (!nps_effect_is_final(chain->effect[i].kind)) {
      x_m = nps_effect_apply(&chain->effect[i], &env, x_m, r);
    }
  }
  x_m = nps_sensor_chain_limit(chain, x_m);
  for (size_t i = 0; chain->has_final && i < chain->n_effects; i++) {
    if (nps_effect_is_final(chain->effect[i].kind)) {
      x_m = nps_effect_apply(&chain->effect[i], &env, x_m, r);
    }
  }
  return x_m;
}

int nps_sensor_chain_check_columns(const struct nps_sensor_chain *chain, const double *const *ctx_column,
                                   char *err, size_t err_len)
{
  for (size_t i = 0; i < chain->n_effects; i++) {
    const struct nps_condition *c = &chain->effect[i].condition;
    const struct nps_bias_curve *curve = &chain->effect[i].curve;
    if (chain->effect[i].kind == NPS_EFFECT_BIAS_CURVE && curve->over_slot >= 0 &&
        (ctx_column == NULL || ctx_column[curve->over_slot] == NULL)) {
      nps_error_set(err, err_len, "bias_curve over '%s' of the %s chain's effect %zu: the log has no such column",
                    curve->over, kind_names[chain->kind], i + 1);
      return -1;
    }
    for (size_t t = 0; t < c->n_terms; t++) {
      if (ctx_column == NULL || ctx_column[c->term[t].slot] == NULL) {
        const bool bare = strcmp(c->text, c->term[t].column) == 0;  /* the condition is that column */
        nps_error_set(err, err_len, "condition '%s' of the %s chain's effect %zu (%s): the log has no %s%s", c->text,
                      kind_names[chain->kind], i + 1, nps_effect_name(chain->effect[i].kind),
                      bare ? "such column" : "column ", bare ? "" : c->term[t].column);
        return -1;
      }
    }
  }
  return 0;
}

int nps_sensor_chain_simulate(const struct nps_sensor_chain *chain, uint64_t seed, size_t n_rows,
                              const double *t_s, const double *true_range_m, const uint32_t *stream_index,
                              size_t n_streams, const int64_t *stream_key, const double *const *ctx_column,
                              double *measured_m, char *err, size_t err_len)
{
  if (nps_sensor_chain_check_columns(chain, ctx_column, err, err_len) != 0) {
    return -1;
  }
  uint64_t sensor = chain->kind == NPS_SENSOR_SONAR ? NPS_RNG_SENSOR_REPLAY_SONAR : NPS_RNG_SENSOR_REPLAY_RANGING;
  struct nps_sensor_state *state = calloc(n_streams ? n_streams : 1, sizeof(*state));
  gsl_rng **rng = calloc(n_streams ? n_streams : 1, sizeof(*rng));
  int rc = (state && rng) ? 0 : -1;
  if (rc != 0) {
    nps_error_set(err, err_len, "out of memory for %zu streams", n_streams);
  }
  for (size_t s = 0; rc == 0 && s < n_streams; s++) {
    nps_sensor_state_init(&state[s]);
  }
  for (size_t i = 0; rc == 0 && i < n_rows; i++) {
    uint32_t s = stream_index[i];
    if (s >= n_streams) {
      nps_error_set(err, err_len, "row %zu: stream index %u, but there are %zu streams", i, s, n_streams);
      rc = -1;
      break;
    }
    if (rng[s] == NULL && (rng[s] = nps_rng_stream_new(seed, (uint64_t)stream_key[s], sensor)) == NULL) {
      nps_error_set(err, err_len, "out of memory for a random stream");
      rc = -1;
      break;
    }
    struct nps_sensor_ctx ctx = {0};
    for (int slot = 0; ctx_column != NULL && slot < NPS_CTX_SLOTS; slot++) {
      if (ctx_column[slot] != NULL) {
        nps_sensor_ctx_set(&ctx, slot, ctx_column[slot][i]);
      }
    }
    measured_m[i] = nps_sensor_chain_apply(chain, t_s[i], true_range_m[i], &ctx, &state[s], rng[s]);
  }
  for (size_t s = 0; rng != NULL && s < n_streams; s++) {
    if (rng[s] != NULL) {
      gsl_rng_free(rng[s]);
    }
  }
  free(rng);
  free(state);
  return rc;
}

size_t nps_sensor_chain_effect_count(const struct nps_sensor_chain *chain)
{
  return chain->n_effects;
}

const struct nps_effect *nps_sensor_chain_effect(const struct nps_sensor_chain *chain, size_t i)
{
  return i < chain->n_effects ? &chain->effect[i] : NULL;
}

int nps_sensor_chain_kind(const struct nps_sensor_chain *chain)
{
  return (int)chain->kind;
}

double nps_sensor_chain_min_range(const struct nps_sensor_chain *chain)
{
  return chain->min_range_m;
}

double nps_sensor_chain_max_range(const struct nps_sensor_chain *chain)
{
  return chain->max_range_m;
}

const char *nps_sensor_chain_beyond_max(const struct nps_sensor_chain *chain)
{
  return chain->beyond_max == NPS_BEYOND_MAX_REPORT_MAX ? "max" : "none";
}

double nps_sensor_chain_speed_of_sound(const struct nps_sensor_chain *chain)
{
  return chain->speed_of_sound_mps;
}
