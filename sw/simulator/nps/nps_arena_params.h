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
 * @file nps_arena_params.h
 * The numeric parameters of the arena configuration, one table per XML element: attribute name, place in
 * the struct, allowed range and unit. The XML loader and the check of configurations built in code use
 * the same tables, so a value is judged the same way whatever its origin.
 */

#ifndef NPS_ARENA_PARAMS_H
#define NPS_ARENA_PARAMS_H

#include <stddef.h>

/** Type of a parameter. */
enum nps_arena_param_type {
  NPS_ARENA_PARAM_INT,          /**< int, whole number */
  NPS_ARENA_PARAM_DOUBLE        /**< double, finite */
};

/** One numeric attribute. */
struct nps_arena_param_spec {
  const char *name;             /**< XML attribute name */
  size_t offset;                /**< offset of the value in its struct */
  enum nps_arena_param_type type;
  double min;                   /**< smallest allowed value ... */
  int min_exclusive;            /**< ... excluded if 1 */
  double max;                   /**< largest allowed value (inclusive; INFINITY: none) */
  const char *expected;         /**< what a good value is, for messages ("a mass > 0 kg") */
  int zero_is_absent;           /**< 1 if 0 means "not given" and is not checked */
};

/** A table of specs. */
struct nps_arena_param_table {
  const char *element;          /**< XML element name */
  const struct nps_arena_param_spec *specs;
  int count;
};

/** <walls> and <wall>: struct nps_wall_params. */
extern const struct nps_arena_param_table nps_arena_wall_table;
/** <arena>: struct nps_arena_config (numeric attributes; `name` is a string). */
extern const struct nps_arena_param_table nps_arena_arena_table;
/** <copters>: struct nps_arena_config. */
extern const struct nps_arena_param_table nps_arena_copters_table;
/** <sonars>: struct nps_arena_config. */
extern const struct nps_arena_param_table nps_arena_sonars_table;

/** The spec named name in table, or NULL. */
const struct nps_arena_param_spec *nps_arena_param_find(const struct nps_arena_param_table *table,
                                                        const char *name);

/**
 * Parse text as the parameter and store it in base + spec->offset if it is in range.
 * @return 0, or -1 with "name=\"text\": expected ..." in why
 */
int nps_arena_param_parse(const struct nps_arena_param_spec *spec, const char *text, void *base,
                          char *why, size_t why_len);

/** Check every parameter of table stored in base. @return 0, or -1 with "name = value: expected ..." in why */
int nps_arena_param_check_all(const struct nps_arena_param_table *table, const void *base,
                              char *why, size_t why_len);

struct nps_arena_config;

/** The polygon corners of cfg without the closing point, as a malloc'ed array of num_points - 1 (x, y) [m]; NULL on ENOMEM. */
double (*nps_arena_corners(const struct nps_arena_config *cfg))[2];

/** Write "source:line: message" (or "source: message" when line is 0) into err. */
void nps_arena_errf(char *err, size_t err_len, const char *source, int line, const char *fmt, ...)
__attribute__((format(printf, 5, 6)));

#endif /* NPS_ARENA_PARAMS_H */
