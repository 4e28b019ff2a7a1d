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
 * @file nps_condition.h
 * Conditions of sensor-model effects: small expressions over the context columns of a reading.
 *
 *   condition := term ["and" term]             (at most NPS_EFFECT_CONDITION_TERMS terms)
 *   term      := column                        holds where the column is non-zero
 *              | column op number              op: == != < <= > >=; number: nps_effect_parse_number
 *
 * e.g. "ctx_blocked", "ctx_nlos == 0 and ctx_rssi < -85.5" (spaces around an operator are optional). A NaN value
 * satisfies no term, not even "!=". One parser serves the model loaders (the XML `condition` attribute, the
 * one-line form's "if ...") and the Python tools (nps_condition_mask).
 *
 * Canonical text: the terms joined by " and ", a non-zero term as its bare column, any other as
 * "column op number", the number in the fewest digits that read back as the same double, written as Python's
 * repr(float) writes them but without a trailing ".0" ("0", "-85.5", "1e-05", "1e+16").
 */

#ifndef NPS_CONDITION_H
#define NPS_CONDITION_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "nps_sensor_model_ctx.h"

#define NPS_EFFECT_CONDITION_TERMS 2
/** Room for a canonical text: two terms of a 47-character column, " <= " and a 24-character number, " and ". */
#define NPS_CONDITION_TEXT_LEN 160

enum nps_condition_op {
  NPS_CONDITION_NONZERO, NPS_CONDITION_EQ, NPS_CONDITION_NE, NPS_CONDITION_LT, NPS_CONDITION_LE, NPS_CONDITION_GT,
  NPS_CONDITION_GE
};

struct nps_condition_term {
  char column[NPS_CTX_NAME_LEN];
  enum nps_condition_op op;
  double value;            /**< the number the column is compared with (not for NPS_CONDITION_NONZERO) */
  int slot;                /**< the column's context slot in a model (nps_sensor_model_add_effect), else -1 */
};

struct nps_condition {
  size_t n_terms;          /**< 0: always holds */
  struct nps_condition_term term[NPS_EFFECT_CONDITION_TERMS];
  char text[NPS_CONDITION_TEXT_LEN];   /**< canonical text, "" for none */
};

/**
 * Parse the `len` bytes of `text` (the grammar above; no context column is checked here).
 * @param err_pos  receives the offset in text where the error is (may be NULL)
 * @return 0, or -1 with "condition '<text>': reason" in err
 */
int nps_condition_parse(struct nps_condition *cond, const char *text, size_t len, size_t *err_pos,
                        char *err, size_t err_len);

/** Whether a term holds for a column value (NaN: never). */
static inline bool nps_condition_term_holds(const struct nps_condition_term *term, double v)
{
  switch (term->op) {
    case NPS_CONDITION_NONZERO: return v != 0.0 && !isnan(v);
    case NPS_CONDITION_EQ: return v == term->value;
    case NPS_CONDITION_NE: return v != term->value && !isnan(v);
    case NPS_CONDITION_LT: return v < term->value;
    case NPS_CONDITION_LE: return v <= term->value;
    case NPS_CONDITION_GT: return v > term->value;
    case NPS_CONDITION_GE: return v >= term->value;
    default: return false;
  }
}

/** Whether every term holds for the context of a reading (its slots; NULL ctx: all zero). */
static inline bool nps_condition_holds(const struct nps_condition *cond, const struct nps_sensor_ctx *ctx)
{
  for (size_t t = 0; t < cond->n_terms; t++) {
    if (!nps_condition_term_holds(&cond->term[t], nps_sensor_ctx_get(ctx, cond->term[t].slot))) {
      return false;
    }
  }
  return true;
}

/*
 * For bindings (NUL-terminated condition texts):
 * nps_condition_mask: out[i] = 1 where the condition holds on row i of the columns, else 0; column j is named
 *   column_name[j] and holds n values. -1 with the reason for a malformed condition or a column not given.
 * nps_condition_canonical: the canonical text into out; -1 with the reason.
 * nps_condition_columns: the columns its terms name, each once, in order, separated by ' ', into out; returns
 *   how many, or -1 with the reason.
 */
int nps_condition_mask(const char *condition, size_t n_columns, const char *const column_name[],
                       const double *const column[], size_t n, unsigned char *out, char *err, size_t err_len);
int nps_condition_canonical(const char *condition, char *out, size_t out_len, char *err, size_t err_len);
int nps_condition_columns(const char *condition, char *out, size_t out_len, char *err, size_t err_len);

#endif /* NPS_CONDITION_H */
