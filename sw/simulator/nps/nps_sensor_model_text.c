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
 * @file nps_sensor_model_text.c
 * Sensor models from one line of text, e.g. an airframe define:
 *
 *   model   := chain ('|' chain)*
 *   chain   := kind ['(' kv (',' kv)* ')'] [':' [effect (';' effect)*]]
 *   effect  := name ['(' kv (',' kv)* ')'] ['if' condition]
 *   kv      := key '=' value          (value: a number, max/none, a mixture file path, a column name, or a list
 *                                      of numbers separated by spaces: glitch values, bias_curve at and b)
 *
 *   "sonar(min_range=0.2, max_range=3): rayleigh_short(sigma=0.05); crosstalk(p=0.68)
 *    | ranging: gmm(mixture=conf/sensor_models/finken_ranging_gmm_k100.xml); gaussian(sigma=0.1) if ctx_blocked;
 *      bias(b=0.3) if ctx_blocked and ctx_wall_dist < 0.5; bias_curve(over=true_range, at=0 1 2, b=0 0.02 0.03);
 *      glitch(p=0.001, values=-12.84 0 inf)"
 *
 * A condition (nps_condition.h) is the rest of the effect, up to ';', '|' or the end, and names context columns
 * its user has (nps_sensor_model_check_effect_columns; so does a bias_curve's over). Mixture paths are relative to
 * the working directory; the text holds no NUL byte.
 */

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nps_sensor_model.h"
#include "nps_sensor_model_xml.h"

/** Most key=value pairs in one (...) list; longest name or key; longest value (64 numbers of 25 characters). */
#define TEXT_MAX_KV 8
#define TEXT_MAX_TOKEN 256
#define TEXT_MAX_VALUE (NPS_GLITCH_MAX_VALUES * 26)

struct text_parser {
  const char *text;
  size_t pos;
  const char *origin;
  size_t n_log_columns;               /**< a replayed log's ctx_ columns a condition may name too */
  const char *const *log_column;
  char *err;
  size_t err_len;
};

struct kv_list {
  size_t n;
  char key[TEXT_MAX_KV][TEXT_MAX_TOKEN];
  char value[TEXT_MAX_KV][TEXT_MAX_VALUE];
  const char *key_ptr[TEXT_MAX_KV];
  const char *value_ptr[TEXT_MAX_KV];
};

/** Error at the current position: "origin:1: reason (column c)". */
static int fail(struct text_parser *p, const char *fmt, ...)
{
  if (p->err == NULL || p->err_len == 0) {
    return -1;
  }
  char reason[NPS_SENSOR_MODEL_ERR_LEN];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof(reason), fmt, ap);
  va_end(ap);
  snprintf(p->err, p->err_len, "%s:1: %s (column %zu)", p->origin, reason, p->pos + 1);
  return -1;
}

/** Prefix a reason the model builder left in err with the position. */
static int fail_builder(struct text_parser *p, size_t pos)
{
  char reason[NPS_SENSOR_MODEL_ERR_LEN];
  snprintf(reason, sizeof(reason), "%s", p->err ? p->err : "");
  p->pos = pos;
  return fail(p, "%s", reason);
}

static void skip_space(struct text_parser *p)
{
  while (isspace((unsigned char)p->text[p->pos])) {
    p->pos++;
  }
}

static bool accept(struct text_parser *p, char c)
{
  skip_space(p);
  if (p->text[p->pos] == c) {
    p->pos++;
    return true;
  }
  return false;
}

/** An identifier [A-Za-z_][A-Za-z0-9_]* into out; -1 with an error naming `what` otherwise. */
static int identifier(struct text_parser *p, char *out, const char *what)
{
  skip_space(p);
  size_t start = p->pos, n = 0;
  while (isalnum((unsigned char)p->text[p->pos]) || p->text[p->pos] == '_') {
    p->pos++;
  }
  n = p->pos - start;
  if (n == 0 || isdigit((unsigned char)p->text[start]) || n >= TEXT_MAX_TOKEN) {
    p->pos = start;
    return fail(p, "expected %s", what);
  }
  memcpy(out, p->text + start, n);
  out[n] = '\0';
  return 0;
}

/** A value: everything up to ',' or ')' with surrounding space removed. */
static int value(struct text_parser *p, char *out)
{
  skip_space(p);
  size_t start = p->pos;
  while (p->text[p->pos] != '\0' && p->text[p->pos] != ',' && p->text[p->pos] != ')') {
    p->pos++;
  }
  size_t end = p->pos;
  while (end > start && isspace((unsigned char)p->text[end - 1])) {
    end--;
  }
  if (end == start) {
    p->pos = start;
    return fail(p, "expected a value");
  }
  if (end - start >= TEXT_MAX_VALUE) {
    p->pos = start;
    return fail(p, "a value longer than %d characters", TEXT_MAX_VALUE - 1);
  }
  memcpy(out, p->text + start, end - start);
  out[end - start] = '\0';
  return 0;
}

/** An optional '(' key=value, ... ')' list. */
static int kv_list(struct text_parser *p, struct kv_list *kv)
{
  kv->n = 0;
  if (!accept(p, '(')) {
    return 0;
  }
  if (accept(p, ')')) {
    return 0;
  }
  do {
    if (kv->n == TEXT_MAX_KV) {
      return fail(p, "more than %d key=value pairs", TEXT_MAX_KV);
    }
    if (identifier(p, kv->key[kv->n], "a parameter name") != 0) {
      return -1;
    }
    if (!accept(p, '=')) {
      return fail(p, "expected '=' after '%s'", kv->key[kv->n]);
    }
    if (value(p, kv->value[kv->n]) != 0) {
      return -1;
    }
    kv->key_ptr[kv->n] = kv->key[kv->n];
    kv->value_ptr[kv->n] = kv->value[kv->n];
    kv->n++;
  } while (accept(p, ','));
  return accept(p, ')') ? 0 : fail(p, "expected ',' or ')'");
}

/** Remove key `key` from kv, copying its value to out (TEXT_MAX_VALUE bytes; else empty); returns whether found. */
static bool take_kv(struct kv_list *kv, const char *key, char *out)
{
  out[0] = '\0';
  for (size_t i = 0; i < kv->n; i++) {
    if (strcmp(kv->key[i], key) == 0) {
      snprintf(out, TEXT_MAX_VALUE, "%s", kv->value[i]);
      kv->n--;
      memcpy(kv->key[i], kv->key[kv->n], TEXT_MAX_TOKEN);
      memcpy(kv->value[i], kv->value[kv->n], TEXT_MAX_VALUE);
      return true;
    }
  }
  return false;
}

/** An optional "if condition": the rest of the effect, up to ';', '|' or the end (nps_condition_parse). */
static int effect_condition(struct text_parser *p, struct nps_condition *cond, size_t *condition_pos)
{
  memset(cond, 0, sizeof(*cond));   /* no terms: always */
  skip_space(p);
  char after_if = p->text[p->pos] ? p->text[p->pos + 1] ? p->text[p->pos + 2] : '\0' : '\0';
  if (strncmp(p->text + p->pos, "if", 2) != 0 || !(after_if == '\0' || isspace((unsigned char)after_if))) {
    return 0;
  }
  p->pos += 2;
  skip_space(p);
  *condition_pos = p->pos;
  size_t len = strcspn(p->text + p->pos, ";|");
  while (len > 0 && isspace((unsigned char)p->text[p->pos + len - 1])) {
    len--;
  }
  size_t err_pos = 0;
  char reason[NPS_SENSOR_MODEL_ERR_LEN];
  if (nps_condition_parse(cond, p->text + p->pos, len, &err_pos, reason, sizeof(reason)) != 0) {
    p->pos += err_pos;
    return fail(p, "%s", reason);
  }
  p->pos += len;
  return 0;
}

static int effect(struct text_parser *p, struct nps_sensor_model *model, const char *kind)
{
  char name[TEXT_MAX_TOKEN], mixture[TEXT_MAX_VALUE];
  struct kv_list kv;
  struct nps_condition cond;
  skip_space(p);
  size_t start = p->pos, condition_pos = 0;
  if (identifier(p, name, "an effect name") != 0 || kv_list(p, &kv) != 0 ||
      effect_condition(p, &cond, &condition_pos) != 0) {
    return -1;
  }
  struct nps_gmm *gmm = NULL;
  if (take_kv(&kv, "mixture", mixture)) {
    gmm = nps_sensor_model_load_mixture(mixture, p->err, p->err_len);
    if (gmm == NULL) {
      return fail_builder(p, start);   /* "origin:1: mixture-file:line: reason (column c)" */
    }
  }
  for (size_t i = 0; i < kv.n; i++) {
    kv.key_ptr[i] = kv.key[i];
    kv.value_ptr[i] = kv.value[i];
  }
  if (nps_sensor_model_add_effect(model, kind, name, kv.n, kv.key_ptr, kv.value_ptr, &cond, gmm, p->err,
                                  p->err_len) != 0) {
    return fail_builder(p, start);
  }
  const struct nps_sensor_chain *c = nps_sensor_model_chain(model, kind);
  bool in_condition;
  if (nps_sensor_model_check_effect_columns(&c->effect[c->n_effects - 1], p->n_log_columns, p->log_column,
                                            &in_condition, p->err, p->err_len) != 0) {
    return fail_builder(p, in_condition ? condition_pos : start);
  }
  return 0;
}

static int chain(struct text_parser *p, struct nps_sensor_model *model)
{
  char kind[TEXT_MAX_TOKEN];
  struct kv_list kv;
  skip_space(p);
  size_t start = p->pos;
  if (identifier(p, kind, "sonar or ranging") != 0 || kv_list(p, &kv) != 0) {
    return -1;
  }
  if (nps_sensor_model_add_chain(model, kind, kv.n, kv.key_ptr, kv.value_ptr, p->err, p->err_len) != 0) {
    return fail_builder(p, start);
  }
  skip_space(p);
  if (p->text[p->pos] == '\0' || p->text[p->pos] == '|') {
    return 0;  /* a chain without effects: its range limits only */
  }
  if (!accept(p, ':')) {
    return fail(p, "expected ':' after the %s chain's attributes", kind);
  }
  skip_space(p);
  if (p->text[p->pos] == '\0' || p->text[p->pos] == '|') {
    return 0;
  }
  do {
    if (effect(p, model, kind) != 0) {
      return -1;
    }
  } while (accept(p, ';'));
  return 0;
}

/** The model of the NUL-terminated text of p; -1 with p's error. */
static int parse_model(struct text_parser *p, struct nps_sensor_model **model)
{
  struct nps_sensor_model *m = nps_sensor_model_new();
  if (m == NULL) {
    return fail(p, "out of memory");
  }
  int rc = 0;
  do {
    rc = chain(p, m);
  } while (rc == 0 && accept(p, '|'));
  skip_space(p);
  if (rc == 0 && p->text[p->pos] != '\0') {
    rc = fail(p, "unexpected '%c' (expected ';' between effects or '|' between chains)", p->text[p->pos]);
  }
  if (rc != 0) {
    nps_sensor_model_free(m);
    return -1;
  }
  *model = m;
  return 0;
}

int nps_sensor_model_from_text_for_log(const char *text, size_t len, const char *origin,
                                       size_t n_log_columns, const char *const log_column[],
                                       struct nps_sensor_model **model, char *err, size_t err_len)
{
  struct text_parser p = {.text = "", .pos = 0, .origin = origin ? origin : "model text",
           .n_log_columns = n_log_columns, .log_column = log_column, .err = err, .err_len = err_len
  };
  *model = NULL;
  const char *nul = text ? memchr(text, '\0', len) : NULL;
  if (nul != NULL) {
    p.pos = (size_t)(nul - text);
    return fail(&p, "NUL byte in the model");   /* a C string would end there: the rest was ignored */
  }
  char *copy = malloc(len + 1);   /* the parser reads up to a NUL, which `text` need not have */
  if (copy == NULL) {
    return fail(&p, "out of memory");
  }
  if (len > 0) {
    memcpy(copy, text, len);
  }
  copy[len] = '\0';
  p.text = copy;
  int rc = parse_model(&p, model);
  free(copy);
  return rc;
}

int nps_sensor_model_from_string(const char *text, const char *origin, struct nps_sensor_model **model,
                                 char *err, size_t err_len)
{
  return nps_sensor_model_from_text_for_log(text, text ? strlen(text) : 0, origin, 0, NULL, model, err, err_len);
}

int nps_sensor_model_from_define(const char *value, const char *define_name, struct nps_sensor_model **model,
                                 char *err, size_t err_len)
{
  size_t n = value ? strlen(value) : 0;
  while (n > 0 && isspace((unsigned char)value[n - 1])) {
    n--;
  }
  if (n >= 4 && strncmp(value + n - 4, ".xml", 4) == 0) {
    char path[TEXT_MAX_TOKEN * 4];
    const char *start = value;
    while (isspace((unsigned char)*start)) {
      start++;
      n--;
    }
    snprintf(path, sizeof(path), "%.*s", (int)n, start);
    return nps_sensor_model_load(path, model, err, err_len);
  }
  return nps_sensor_model_from_string(value, define_name, model, err, err_len);
}
