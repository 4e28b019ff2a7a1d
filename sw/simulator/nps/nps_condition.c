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
 * @file nps_condition.c
 * Conditions of sensor-model effects: the parser, the canonical text, the evaluation over columns.
 */

#include "nps_condition.h"
#include "nps_error.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nps_effect.h"

/** Longest number text a term takes (nps_effect_parse_number reads it). */
#define NUMBER_MAX_LEN 64
/** Most bytes of the condition (and of a word in it) an error message quotes. */
#define QUOTE_MAX 200

static const char *const op_text[] = {
  [NPS_CONDITION_NONZERO] = "", [NPS_CONDITION_EQ] = "==", [NPS_CONDITION_NE] = "!=", [NPS_CONDITION_LT] = "<",
  [NPS_CONDITION_LE] = "<=", [NPS_CONDITION_GT] = ">", [NPS_CONDITION_GE] = ">=",
};
#define N_OPS (sizeof(op_text) / sizeof(op_text[0]))

/** A text being parsed and where its error goes. */
struct scan {
  const char *text;
  size_t len, pos;
  size_t *err_pos;
  char *err;
  size_t err_len;
};

static int fail(struct scan *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(struct scan *s, const char *fmt, ...)
{
  char reason[256];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof(reason), fmt, ap);
  va_end(ap);
  if (s->err_pos != NULL) {
    *s->err_pos = s->pos;
  }
  nps_error_set(s->err, s->err_len, "condition '%.*s': %s", (int)(s->len < QUOTE_MAX ? s->len : QUOTE_MAX), s->text,
                reason);
  return -1;
}

static void skip_space(struct scan *s)
{
  while (s->pos < s->len && isspace((unsigned char)s->text[s->pos])) {
    s->pos++;
  }
}

static bool is_name_char(char c)
{
  return isalnum((unsigned char)c) || c == '_';
}

static bool is_op_char(char c)
{
  return c == '=' || c == '!' || c == '<' || c == '>';
}

static bool is_not_space(char c)
{
  return !isspace((unsigned char)c);
}

/** Length of the run of characters in_run accepts at the current position. */
static size_t run_length(const struct scan *s, bool (*in_run)(char))
{
  size_t n = 0;
  while (s->pos + n < s->len && in_run(s->text[s->pos + n])) {
    n++;
  }
  return n;
}

/** Whether the word `w` (not the start of a longer name) is at the current position. */
static bool word_at(const struct scan *s, const char *w)
{
  const size_t n = strlen(w);
  return s->len - s->pos >= n && strncmp(s->text + s->pos, w, n) == 0 &&
         (s->pos + n == s->len || !is_name_char(s->text[s->pos + n]));
}

/** One term: column [op number]. */
static int term(struct scan *s, struct nps_condition_term *t, bool after_and)
{
  const size_t n = run_length(s, is_name_char);
  if (n == 0 || isdigit((unsigned char)s->text[s->pos])) {
    return fail(s, "expected a context column%s", after_and ? " after 'and'" : "");
  }
  if (n >= NPS_CTX_NAME_LEN) {
    return fail(s, "a column name has at most %d characters", NPS_CTX_NAME_LEN - 1);
  }
  memcpy(t->column, s->text + s->pos, n);
  t->column[n] = '\0';
  t->op = NPS_CONDITION_NONZERO;
  t->slot = -1;
  s->pos += n;
  skip_space(s);
  const size_t n_op = run_length(s, is_op_char);
  if (n_op == 0) {
    return 0;
  }
  size_t k = 1;
  while (k < N_OPS && !(strlen(op_text[k]) == n_op && strncmp(s->text + s->pos, op_text[k], n_op) == 0)) {
    k++;
  }
  if (k == N_OPS) {
    return fail(s, "unknown operator '%.*s' (expected ==, !=, <, <=, >, >=)", (int)n_op, s->text + s->pos);
  }
  t->op = (enum nps_condition_op)k;
  s->pos += n_op;
  skip_space(s);
  const size_t n_num = run_length(s, is_not_space);
  char number[NUMBER_MAX_LEN];
  if (n_num == 0) {
    return fail(s, "expected a number after '%s'", op_text[k]);
  }
  if (n_num < sizeof(number)) {
    memcpy(number, s->text + s->pos, n_num);
    number[n_num] = '\0';
  }
  if (n_num >= sizeof(number) || nps_effect_parse_number(number, &t->value) != 0) {
    return fail(s, "'%.*s' is not a finite number", (int)(n_num < QUOTE_MAX ? n_num : QUOTE_MAX), s->text + s->pos);
  }
  s->pos += n_num;
  return 0;
}

/** The fewest digits of v that strtod reads back as v: as Python's repr(float), without a trailing ".0". */
static void format_number(double v, char *out, size_t len)
{
  for (int digits = 1; digits <= 17; digits++) {
    char sci[32];
    snprintf(sci, sizeof(sci), "%.*e", digits - 1, v);
    const int exp10 = atoi(strchr(sci, 'e') + 1);
    if (exp10 < -4 || exp10 >= 16) {
      snprintf(out, len, "%s", sci);
    } else {
      snprintf(out, len, "%.*f", digits - 1 - exp10 > 0 ? digits - 1 - exp10 : 0, v);
    }
    if (strtod(out, NULL) == v) {
      return;
    }
  }
}

static void format_text(struct nps_condition *cond)
{
  size_t used = 0;
  for (size_t t = 0; t < cond->n_terms; t++) {
    const struct nps_condition_term *term = &cond->term[t];
    char number[32] = "";
    if (term->op != NPS_CONDITION_NONZERO) {
      format_number(term->value, number, sizeof(number));
    }
    int w = snprintf(cond->text + used, sizeof(cond->text) - used, "%s%s%s%s%s%s", t ? " and " : "", term->column,
                     number[0] ? " " : "", op_text[term->op], number[0] ? " " : "", number);
    used += w > 0 ? (size_t)w : 0;
  }
}

int nps_condition_parse(struct nps_condition *cond, const char *text, size_t len, size_t *err_pos,
                        char *err, size_t err_len)
{
  struct scan s = {.text = text, .len = len, .pos = 0, .err_pos = err_pos, .err = err, .err_len = err_len};
  memset(cond, 0, sizeof(*cond));
  skip_space(&s);
  for (;;) {
    struct nps_condition_term *t = &cond->term[cond->n_terms++];
    if (term(&s, t, cond->n_terms > 1) != 0) {
      return -1;
    }
    skip_space(&s);
    if (s.pos == s.len) {
      break;
    }
    if (word_at(&s, "or")) {
      return fail(&s, "'or' is not supported (terms are joined by 'and')");
    }
    if (!word_at(&s, "and")) {
      const size_t n = run_length(&s, is_not_space);
      return fail(&s, "unexpected '%.*s' (expected %s'and' or the end)", (int)(n < QUOTE_MAX ? n : QUOTE_MAX),
                  s.text + s.pos, t->op == NPS_CONDITION_NONZERO ? "an operator (==, !=, <, <=, >, >=), " : "");
    }
    if (cond->n_terms == NPS_EFFECT_CONDITION_TERMS) {
      return fail(&s, "at most %d terms are joined by 'and'", NPS_EFFECT_CONDITION_TERMS);
    }
    s.pos += strlen("and");
    skip_space(&s);
  }
  format_text(cond);
  return 0;
}

/** Parse a NUL-terminated text (NULL: none, refused). */
static int parse_string(struct nps_condition *cond, const char *text, char *err, size_t err_len)
{
  return nps_condition_parse(cond, text ? text : "", text ? strlen(text) : 0, NULL, err, err_len);
}

int nps_condition_mask(const char *condition, size_t n_columns, const char *const column_name[],
                       const double *const column[], size_t n, unsigned char *out, char *err, size_t err_len)
{
  struct nps_condition cond;
  if (parse_string(&cond, condition, err, err_len) != 0) {
    return -1;
  }
  const double *value[NPS_EFFECT_CONDITION_TERMS];
  for (size_t t = 0; t < cond.n_terms; t++) {
    value[t] = NULL;
    for (size_t j = 0; j < n_columns && value[t] == NULL; j++) {
      value[t] = strcmp(column_name[j], cond.term[t].column) == 0 ? column[j] : NULL;
    }
    if (value[t] == NULL) {
      nps_error_set(err, err_len, "condition '%s': no column '%s' was given", cond.text, cond.term[t].column);
      return -1;
    }
  }
  for (size_t i = 0; i < n; i++) {
    bool holds = true;
    for (size_t t = 0; holds && t < cond.n_terms; t++) {
      holds = nps_condition_term_holds(&cond.term[t], value[t][i]);
    }
    out[i] = holds;
  }
  return 0;
}

int nps_condition_canonical(const char *condition, char *out, size_t out_len, char *err, size_t err_len)
{
  struct nps_condition cond;
  if (parse_string(&cond, condition, err, err_len) != 0) {
    return -1;
  }
  snprintf(out, out_len, "%s", cond.text);
  return 0;
}

int nps_condition_columns(const char *condition, char *out, size_t out_len, char *err, size_t err_len)
{
  struct nps_condition cond;
  if (parse_string(&cond, condition, err, err_len) != 0) {
    return -1;
  }
  char columns[NPS_CONDITION_TEXT_LEN] = "";
  int n = 0;
  for (size_t t = 0; t < cond.n_terms; t++) {
    if (t > 0 && strcmp(cond.term[t].column, cond.term[0].column) == 0) {
      continue;  /* named by the first term already (two terms at most) */
    }
    const size_t used = strlen(columns);
    snprintf(columns + used, sizeof(columns) - used, "%s%s", n ? " " : "", cond.term[t].column);
    n++;
  }
  snprintf(out, out_len, "%s", columns);
  return n;
}
