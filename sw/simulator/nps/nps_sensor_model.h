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
 * @file nps_sensor_model.h
 * Sensor models: per sensor kind (sonar, ranging) an ordered chain of error effects (nps_effect.h)
 * followed by the sensor's range limits. One implementation serves the NPS host and the Python tools.
 *
 * Applying a chain to one reading (nps_sensor_chain_apply):
 *   1. remember (t, true range) in the stream state (for latency);
 *   2. x = true range, or +inf ("no echo") when the true range exceeds max_range;
 *   3. x = effect_n(... effect_1(x)) over the effects but glitches, each only where its condition holds;
 *   4. NaN stays NaN (no reading); +inf gives max_range (beyond_max "max") or NaN (beyond_max "none");
 *      a finite x is clamped to [min_range, max_range];
 *   5. the glitches in file order, each where its condition holds: a glitch's reading is final (not clamped).
 *
 * Sources of a model (file format in docs/sensors.md, "Model file format"):
 *   - an XML model file: nps_sensor_model_load();
 *   - an inline text, e.g. from an airframe define: nps_sensor_model_from_string(), or
 *     nps_sensor_model_from_define() which accepts either a model file path or an inline text;
 *   - code: nps_sensor_model_new(), nps_sensor_model_add_chain(), nps_sensor_model_add_effect().
 * Loading either succeeds completely or returns -1 with "file:line: reason" and no model. The loaders are the
 * one grammar of models (the Python tools call them too): a model is text without NUL bytes, an XML model
 * takes no DOCTYPE (no DTD, no entities), and a condition (nps_condition.h, e.g. "ctx_blocked" or
 * "ctx_nlos == 0 and ctx_rssi < -85.5") must name context columns its user has: the simulator's
 * (nps_sensor_ctx_fixed_name: the ctx_ columns of the range logs it writes, and ctx_vehicle, their vehicle column)
 * or, for the replay of a range log (the *_for_log loaders), that log's ctx_ columns. So must a bias_curve's `over`.
 */

#ifndef NPS_SENSOR_MODEL_H
#define NPS_SENSOR_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <gsl/gsl_rng.h>

#include "nps_effect.h"
#include "nps_gmm.h"
#include "nps_sensor_model_ctx.h"

#define NPS_SENSOR_CHAIN_MAX_EFFECTS 16
/** Room for an error message "file:line: reason". */
#define NPS_SENSOR_MODEL_ERR_LEN 512

enum nps_sensor_kind { NPS_SENSOR_SONAR, NPS_SENSOR_RANGING, NPS_SENSOR_KINDS };

/** What a sensor reports when there is no echo within its range. */
enum nps_beyond_max {
  NPS_BEYOND_MAX_REPORT_MAX,  /**< "max": the maximum range */
  NPS_BEYOND_MAX_NO_READING   /**< "none": no reading (NaN) */
};

struct nps_sensor_chain {
  enum nps_sensor_kind kind;
  double min_range_m;         /**< readings below are raised to it [m] */
  double max_range_m;         /**< readings above are lowered to it; true ranges above give no echo [m] */
  enum nps_beyond_max beyond_max;
  double speed_of_sound_mps;  /**< for crosstalk [m/s] */
  size_t n_effects;
  struct nps_effect effect[NPS_SENSOR_CHAIN_MAX_EFFECTS];
  bool reads_state;           /**< it has a latency effect (kept by nps_sensor_model_add_effect) */
  bool has_final;             /**< it has a glitch, applied after the limits (nps_effect_is_final; kept likewise) */
};

struct nps_sensor_model {
  bool has_chain[NPS_SENSOR_KINDS];
  struct nps_sensor_chain chain[NPS_SENSOR_KINDS];
  size_t n_gmm;
  struct nps_gmm *gmm[NPS_SENSOR_KINDS * NPS_SENSOR_CHAIN_MAX_EFFECTS]; /**< owned mixtures */
  size_t n_ctx_extra;
  char ctx_extra[NPS_CTX_EXTRA_MAX][NPS_CTX_NAME_LEN]; /**< column names of slots NPS_CTX_EXTRA0 + i */
  char *name;                 /**< the model file's name attribute (owned), NULL when it has none */
};

/** "sonar" / "ranging" -> kind, or -1. */
int nps_sensor_kind_from_name(const char *name);

/* ---- loading ---- */

/** Load an XML model file (mixture files it names are read relative to its directory). */
int nps_sensor_model_load(const char *path, struct nps_sensor_model **model, char *err, size_t err_len);
/** Load an XML model from memory; `origin` names it in errors, `base_dir` resolves mixture files (NULL: "."). */
int nps_sensor_model_load_memory(const char *xml, size_t len, const char *origin, const char *base_dir,
                                 struct nps_sensor_model **model, char *err, size_t err_len);
/**
 * Build a model from an inline text (grammar in docs/sensors.md, "One-line form"), e.g.
 *   "sonar(min_range=0.2, max_range=3, beyond_max=max): rayleigh_short(sigma=0.05); crosstalk(p=0.68)
 *    | ranging(max_range=2.5): gmm(mixture=conf/sensor_models/finken_ranging_gmm_k100.xml)"
 * `origin` names the text in errors ("origin:1: reason (column c)").
 */
int nps_sensor_model_from_string(const char *text, const char *origin, struct nps_sensor_model **model,
                                 char *err, size_t err_len);
/** An airframe define's value: a model file path (ends in ".xml") or an inline text; `define_name` for errors. */
int nps_sensor_model_from_define(const char *value, const char *define_name, struct nps_sensor_model **model,
                                 char *err, size_t err_len);
/*
 * The loaders above for the replay of a range log: conditions may also name the log's own ctx_ columns
 * (log_column[0 .. n_log_columns - 1]). The inline text is `len` bytes (a NUL byte among them is refused).
 */
int nps_sensor_model_load_for_log(const char *path, size_t n_log_columns, const char *const log_column[],
                                  struct nps_sensor_model **model, char *err, size_t err_len);
int nps_sensor_model_load_memory_for_log(const char *xml, size_t len, const char *origin, const char *base_dir,
    size_t n_log_columns, const char *const log_column[],
    struct nps_sensor_model **model, char *err, size_t err_len);
int nps_sensor_model_from_text_for_log(const char *text, size_t len, const char *origin,
                                       size_t n_log_columns, const char *const log_column[],
                                       struct nps_sensor_model **model, char *err, size_t err_len);
void nps_sensor_model_free(struct nps_sensor_model *model);
/** The model file's name attribute, NULL when it has none. */
const char *nps_sensor_model_name(const struct nps_sensor_model *model);

/* ---- building from code (the loaders use these) ---- */

struct nps_sensor_model *nps_sensor_model_new(void);
/**
 * Add the chain of a kind; attributes as text: min_range, max_range [m], beyond_max ("max"|"none"),
 * speed_of_sound [m/s]. Defaults: sonar [0.2, 3.0] m, ranging [0, 2.5] m, "max", 343 m/s.
 */
int nps_sensor_model_add_chain(struct nps_sensor_model *model, const char *kind, size_t n_attrs,
                               const char *const key[], const char *const value[], char *err, size_t err_len);
/**
 * Append an effect to the chain of a kind. Parameters as text (nps_effect_init_text); `condition` parsed by
 * nps_condition_parse, or NULL: each of its columns, and a bias_curve's `over` column, gets a context slot (whether
 * its user has the column is the loaders' check, nps_sensor_model_check_effect_columns); `gmm` the mixture of a gmm
 * effect (ownership passes to the model, also on error).
 */
int nps_sensor_model_add_effect(struct nps_sensor_model *model, const char *kind, const char *name,
                                size_t n_params, const char *const key[], const char *const value[],
                                const struct nps_condition *condition, struct nps_gmm *gmm, char *err, size_t err_len);

/* ---- use ---- */

/** The chain of "sonar" or "ranging", or NULL when the model has none. */
const struct nps_sensor_chain *nps_sensor_model_chain(const struct nps_sensor_model *model, const char *kind);
/** The same by kind (no name look-up: for the per-reading paths). */
const struct nps_sensor_chain *nps_sensor_model_chain_of(const struct nps_sensor_model *model,
    enum nps_sensor_kind kind);
/** The context slot a column name refers to (fixed or model-defined), or -1. */
int nps_sensor_model_ctx_slot(const struct nps_sensor_model *model, const char *column);
/** The column name of a slot, or NULL when the slot is unused by this model. */
const char *nps_sensor_model_ctx_slot_name(const struct nps_sensor_model *model, int slot);
/**
 * Whether a column a condition names is one its user has: the simulator's, or one of a replayed log's
 * (log_column[0 .. n_log_columns - 1]; none for the simulator). -1 with a reason naming it and the known ones.
 */
int nps_sensor_model_check_column(const char *column, size_t n_log_columns, const char *const log_column[],
                                  char *err, size_t err_len);
/**
 * nps_sensor_model_check_column for every column an effect names: its condition's, then a bias_curve's `over`.
 * @param in_condition  receives whether the column refused is the condition's (may be NULL)
 */
int nps_sensor_model_check_effect_columns(const struct nps_effect *effect, size_t n_log_columns,
                                          const char *const log_column[], bool *in_condition,
                                          char *err, size_t err_len);

/**
 * One reading: the measured range [m], or NaN for "no reading" (steps in the file comment).
 * @param ctx    context of the reading (NULL: all zero)
 * @param state  this stream's state, nps_sensor_state_init() once before the first reading (NULL: no latency)
 * @param r      this stream's generator (nps_rng_stream_new())
 */
double nps_sensor_chain_apply(const struct nps_sensor_chain *chain, double t_s, double true_range_m,
                              const struct nps_sensor_ctx *ctx, struct nps_sensor_state *state, gsl_rng *r);

/** Whether the chain reads the stream state (it has a latency effect); if not, a NULL state gives the same readings. */
bool nps_sensor_chain_reads_state(const struct nps_sensor_chain *chain);

/** Step 4 of the file comment on its own. */
double nps_sensor_chain_limit(const struct nps_sensor_chain *chain, double x_m);

/**
 * Log replay: apply a chain to n rows of several streams in one call.
 * Stream s gets its own state and generator nps_rng_stream_new(seed, stream_key[s], NPS_RNG_SENSOR_REPLAY_*).
 * @param stream_index  per row, the stream 0..n_streams-1 (rows of one stream in time order)
 * @param stream_key    per stream, its id (seeds its generator)
 * @param ctx_column    NPS_CTX_SLOTS column pointers (NULL: column absent: 0, crosstalk path = true range;
 *                      a condition's or a bias curve's column must be there, nps_sensor_chain_check_columns)
 * @param measured_m    receives n readings (NaN: no reading)
 * @return 0, or -1 (a condition without its column, out of memory, bad stream index) with the reason in err
 */
int nps_sensor_chain_simulate(const struct nps_sensor_chain *chain, uint64_t seed, size_t n_rows,
                              const double *t_s, const double *true_range_m, const uint32_t *stream_index,
                              size_t n_streams, const int64_t *stream_key, const double *const *ctx_column,
                              double *measured_m, char *err, size_t err_len);

/**
 * Whether the log being replayed has every column the chain's conditions and bias curves name (ctx_column as for
 * nps_sensor_chain_simulate): 0, or -1 with the reason in err naming the first condition or curve and column missing.
 */
int nps_sensor_chain_check_columns(const struct nps_sensor_chain *chain, const double *const *ctx_column,
                                   char *err, size_t err_len);

/* ---- introspection (bindings) ---- */

size_t nps_sensor_chain_effect_count(const struct nps_sensor_chain *chain);
const struct nps_effect *nps_sensor_chain_effect(const struct nps_sensor_chain *chain, size_t i);
int nps_sensor_chain_kind(const struct nps_sensor_chain *chain);
double nps_sensor_chain_min_range(const struct nps_sensor_chain *chain);
double nps_sensor_chain_max_range(const struct nps_sensor_chain *chain);
/** "max" or "none". */
const char *nps_sensor_chain_beyond_max(const struct nps_sensor_chain *chain);
double nps_sensor_chain_speed_of_sound(const struct nps_sensor_chain *chain);

#endif /* NPS_SENSOR_MODEL_H */
