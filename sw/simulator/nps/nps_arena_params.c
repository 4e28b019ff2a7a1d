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
 * @file nps_arena_params.c
 * The numeric parameters of the arena configuration and their allowed ranges (see nps_arena_params.h;
 * the units are justified in docs/arena-and-walls.md).
 */

#include "nps_arena_params.h"
#include "nps_arena.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WALL(name, field, type, min, excl, max, expected, absent) \
  { name, offsetof(struct nps_wall_params, field), type, min, excl, max, expected, absent }
#define CFG(name, field, min, excl, max, expected) \
  { name, offsetof(struct nps_arena_config, field), NPS_ARENA_PARAM_DOUBLE, min, excl, max, expected, 0 }

static const struct nps_arena_param_spec wall_specs[] = {
  WALL("numSegments", num_segments, NPS_ARENA_PARAM_INT, 1, 0, INT_MAX, "a whole number >= 1", 0),
  WALL("wallWidth", wall_width_m, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a wall length > 0 m", 1),
  WALL("segmentMass", segment_mass_kg, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a mass > 0 kg", 0),
  WALL("jointForce", joint_force_nm, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a torque > 0 N m", 0),
  WALL("threshold", threshold_m, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a distance > 0 m", 0),
  WALL("friction", friction_nm, NPS_ARENA_PARAM_DOUBLE, 0, 0, INFINITY, "a torque >= 0 N m", 0),
  /* the law peaks at 1.1 k (x = 1): k <= 80 deg keeps every target below 90 deg */
  WALL("maxAmplitude", max_amplitude_deg, NPS_ARENA_PARAM_DOUBLE, 0, 0, 80,
       "a hinge angle in [0, 80] deg (the law peaks at 1.1 k, below 90 deg)", 0),
  WALL("PID_P", pid_p, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a gain > 0 N m/deg", 0),
  WALL("PID_I", pid_i, NPS_ARENA_PARAM_DOUBLE, 0, 0, INFINITY, "a gain >= 0 N m/(deg s)", 0),
  WALL("PID_D", pid_d, NPS_ARENA_PARAM_DOUBLE, 0, 0, INFINITY, "a gain >= 0 N m s/deg", 0),
  WALL("hingeHeight", hinge_height_m, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a height > 0 m", 0),
  WALL("curtainMass", curtain_mass_kg, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY, "a mass > 0 kg", 0),
  WALL("frictionVelocity", friction_velocity_rad_s, NPS_ARENA_PARAM_DOUBLE, 0, 1, INFINITY,
       "an angular speed > 0 rad/s", 0),
};

static const struct nps_arena_param_spec arena_specs[] = {
  CFG("flightHeight", flight_height_m, 0, 1, INFINITY, "a height > 0 m"),
  CFG("wallHeight", wall_height_m, 0, 1, INFINITY, "a height > 0 m"),
};

static const struct nps_arena_param_spec copters_specs[] = {
  CFG("radius", copter_radius_m, 0, 1, INFINITY, "a radius > 0 m"),
  CFG("height", copter_height_m, 0, 1, INFINITY, "a height > 0 m"),
};

static const struct nps_arena_param_spec sonars_specs[] = {
  CFG("beamHalfAngle", sonar_half_angle_deg, 0, 1, 90, "an angle in (0, 90] deg"),
  CFG("range", sonar_range_m, 0, 1, INFINITY, "a range > 0 m"),
  CFG("offset", sonar_offset_m, 0, 0, INFINITY, "a distance >= 0 m"),
};

#define TABLE(element, specs) { element, specs, (int)(sizeof(specs) / sizeof(specs[0])) }
const struct nps_arena_param_table nps_arena_wall_table = TABLE("walls", wall_specs);
const struct nps_arena_param_table nps_arena_arena_table = TABLE("arena", arena_specs);
const struct nps_arena_param_table nps_arena_copters_table = TABLE("copters", copters_specs);
const struct nps_arena_param_table nps_arena_sonars_table = TABLE("sonars", sonars_specs);

const struct nps_arena_param_spec *nps_arena_param_find(const struct nps_arena_param_table *table,
                                                        const char *name)
{
  for (int i = 0; i < table->count; i++) {
    if (strcmp(table->specs[i].name, name) == 0) {
      return &table->specs[i];
    }
  }
  return NULL;
}

static int in_range(const struct nps_arena_param_spec *s, double v)
{
  if (s->zero_is_absent && v == 0.) {
    return 1;
  }
  int above = s->min_exclusive ? v > s->min : v >= s->min;
  return above && v <= s->max;
}

int nps_arena_param_parse(const struct nps_arena_param_spec *spec, const char *text, void *base,
                          char *why, size_t why_len)
{
  char *end = NULL;
  double v;
  errno = 0;
  if (spec->type == NPS_ARENA_PARAM_INT) {
    long l = strtol(text, &end, 10);
    v = (errno == 0 && l >= INT_MIN && l <= INT_MAX) ? (double)l : NAN;
  } else {
    v = strtod(text, &end);
  }
  while (end && isspace((unsigned char)*end)) {
    end++;
  }
  if (end == text || !end || *end != '\0' || !isfinite(v) || errno != 0 || !in_range(spec, v)) {
    snprintf(why, why_len, "%s=\"%s\": expected %s", spec->name, text, spec->expected);
    return -1;
  }
  char *field = (char *)base + spec->offset;
  if (spec->type == NPS_ARENA_PARAM_INT) {
    *(int *)field = (int)v;
  } else {
    *(double *)field = v;
  }
  return 0;
}

int nps_arena_param_check_all(const struct nps_arena_param_table *table, const void *base,
                              char *why, size_t why_len)
{
  for (int i = 0; i < table->count; i++) {
    const struct nps_arena_param_spec *s = &table->specs[i];
    const char *field = (const char *)base + s->offset;
    double v = s->type == NPS_ARENA_PARAM_INT ? (double) * (const int *)field : *(const double *)field;
    if (!isfinite(v) || !in_range(s, v)) {
      snprintf(why, why_len, "%s = %.9g: expected %s", s->name, v, s->expected);
      return -1;
    }
  }
  return 0;
}

void nps_arena_errf(char *err, size_t err_len, const char *source, int line, const char *fmt, ...)
{
  if (!err || err_len == 0) {
    return;
  }
  int n = line > 0 ? snprintf(err, err_len, "%s:%d: ", source, line) : snprintf(err, err_len, "%s: ", source);
  if (n < 0 || (size_t)n >= err_len) {
    return;
  }
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err + n, err_len - (size_t)n, fmt, ap);
  va_end(ap);
}
