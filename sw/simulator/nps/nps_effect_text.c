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
 * @file nps_effect_text.c
 * Effects from text, as model files write them: numbers, and the text parameters of glitch (values) and bias_curve
 * (over, at, b), lists of numbers and a column name (nps_effect.h).
 */

#include "nps_effect.h"
#include "nps_error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** strtod of the whole text (white space around it allowed; +-inf and NaN too): 0, or -1 (not one double). */
static int parse_double(const char *text, double *value)
{
  if (text == NULL) {
    return -1;
  }
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r') {
    end++;
  }
  if (end == text || *end != '\0' || errno == ERANGE) {
    return -1;
  }
  *value = v;
  return 0;
}

int nps_effect_parse_number(const char *text, double *value)
{
  double v;
  if (parse_double(text, &v) != 0 || !isfinite(v)) {
    return -1;
  }
  *value = v;
  return 0;
}

/**
 * The numbers of a list separated by white space (finite; +-inf too when allow_inf; never NaN), at most max.
 * @return how many, or -1 with "what: reason" naming the bad value
 */
static int parse_list(const char *what, const char *text, bool allow_inf, double *out, size_t max,
                      char *err, size_t err_len)
{
  static const char space[] = " \t\r\n";
  size_t n = 0;
  for (const char *p = text + strspn(text, space); *p != '\0'; p += strspn(p, space)) {
    const size_t len = strcspn(p, space);
    char token[64];
    double v;
    snprintf(token, sizeof(token), "%.*s", (int)len, p);
    if (len >= sizeof(token) || parse_double(token, &v) != 0 || isnan(v) || (isinf(v) && !allow_inf)) {
      nps_error_set(err, err_len, "%s: '%.*s' is not a %s", what, (int)len, p,
                    allow_inf ? "number (finite or +-inf, never NaN)" : "finite number");
      return -1;
    }
    if (n == max) {
      nps_error_set(err, err_len, "%s: more than %zu values", what, max);
      return -1;
    }
    out[n++] = v;
    p += len;
  }
  return (int)n;
}

/** A glitch's values from their text. */
static int set_glitch_values(struct nps_effect *effect, const char *values, char *err, size_t err_len)
{
  const int n = parse_list("glitch values", values, true, effect->value_m, NPS_GLITCH_MAX_VALUES, err, err_len);
  if (n == 0) {
    nps_error_set(err, err_len, "glitch values: none given (1 to %d numbers)", NPS_GLITCH_MAX_VALUES);
  }
  if (n <= 0) {
    return -1;
  }
  effect->n_values = (size_t)n;
  return 0;
}

/** A bias curve from the texts of over, at and b. */
static int set_bias_curve(struct nps_bias_curve *c, const char *over, const char *at, const char *b,
                          char *err, size_t err_len)
{
  if (strlen(over) >= sizeof(c->over)) {
    nps_error_set(err, err_len, "bias_curve over '%s' is longer than %zu characters", over, sizeof(c->over) - 1);
    return -1;
  }
  snprintf(c->over, sizeof(c->over), "%s", over);
  c->over_slot = strcmp(over, "true_range") == 0 ? -1 : NPS_CTX_SLOTS;
  const int n_at = parse_list("bias_curve at", at, false, c->at, NPS_BIAS_CURVE_MAX_KNOTS, err, err_len);
  const int n_b = n_at < 0 ? -1 : parse_list("bias_curve b", b, false, c->b_m, NPS_BIAS_CURVE_MAX_KNOTS, err, err_len);
  if (n_b < 0) {
    return -1;
  }
  if (n_at != n_b || n_at < NPS_BIAS_CURVE_MIN_KNOTS) {
    nps_error_set(err, err_len, "bias_curve: at has %d values and b has %d (need %d to %d knots, one b per knot)",
                  n_at, n_b, NPS_BIAS_CURVE_MIN_KNOTS, NPS_BIAS_CURVE_MAX_KNOTS);
    return -1;
  }
  for (int i = 1; i < n_at; i++) {
    if (!(c->at[i] > c->at[i - 1])) {
      nps_error_set(err, err_len, "bias_curve at: the knots must increase strictly (%.15g then %.15g)", c->at[i - 1],
                    c->at[i]);
      return -1;
    }
  }
  c->n_knots = (size_t)n_at;
  return 0;
}

int nps_effect_init_text(struct nps_effect *effect, const char *name, size_t n_params, const char *const key[],
                         const char *const text[], char *err, size_t err_len)
{
  enum { MAX_KEYS = NPS_EFFECT_MAX_PARAMS + NPS_EFFECT_MAX_TEXT_PARAMS };
  const int kind = nps_effect_kind_from_name(name);
  const char *number_key[MAX_KEYS], *text_value[NPS_EFFECT_MAX_TEXT_PARAMS] = {NULL};
  double number[MAX_KEYS];
  size_t n_numbers = 0;
  if (n_params > MAX_KEYS) {
    nps_error_set(err, err_len, "effect '%s' has %zu parameters, more than any effect takes", name, n_params);
    return -1;
  }
  for (size_t i = 0; i < n_params; i++) {
    const int j = nps_effect_text_param_index(kind, key[i]);
    if (j >= 0 && text_value[j] != NULL) {
      nps_error_set(err, err_len, "parameter '%s' of effect '%s' given twice", key[i], name);
      return -1;
    }
    if (j >= 0) {
      text_value[j] = text[i];
    } else if (nps_effect_parse_number(text[i], &number[n_numbers]) != 0) {
      nps_error_set(err, err_len, "effect '%s' parameter '%s' = '%s' is not a finite number", name, key[i], text[i]);
      return -1;
    } else {
      number_key[n_numbers++] = key[i];
    }
  }
  if (nps_effect_init(effect, name, n_numbers, number_key, number, err, err_len) != 0) {
    return -1;
  }
  for (size_t j = 0; j < nps_effect_text_param_count(kind); j++) {
    if (text_value[j] == NULL) {
      nps_error_set(err, err_len, "effect '%s' needs parameter '%s'", name, nps_effect_text_param_name(kind, j));
      return -1;
    }
  }
  if (kind == NPS_EFFECT_GLITCH) {
    return set_glitch_values(effect, text_value[0], err, err_len);
  }
  if (kind == NPS_EFFECT_BIAS_CURVE) {
    return set_bias_curve(&effect->curve, text_value[0], text_value[1], text_value[2], err, err_len);
  }
  return 0;
}
