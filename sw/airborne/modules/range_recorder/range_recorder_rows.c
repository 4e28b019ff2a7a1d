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
 * @file modules/range_recorder/range_recorder_rows.c
 * The range recorder's pure part: rows, names, paths, clock (see range_recorder_rows.h).
 */

#include "modules/range_recorder/range_recorder_rows.h"
#include "modules/wall_detector/wall_detector_reading.h"   /* wall_detector_class_name: the names of detections.csv */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** The range log's sensor names (shared/spec/range-log.md), by code. */
static const char *const sensor_names[RANGE_RECORDER_SENSOR_NB] = {
  [RANGE_RECORDER_SONAR_FRONT] = "sonar_front", [RANGE_RECORDER_SONAR_RIGHT] = "sonar_right",
  [RANGE_RECORDER_SONAR_BACK] = "sonar_back", [RANGE_RECORDER_SONAR_LEFT] = "sonar_left",
  [RANGE_RECORDER_SONAR_DOWN] = "sonar_down", [RANGE_RECORDER_RANGING] = "ranging",
};

/** Text of a value for a number column. */
#define NUMBER_LEN 32

const char *range_recorder_sensor_name(uint8_t sensor)
{
  return sensor < RANGE_RECORDER_SENSOR_NB ? sensor_names[sensor] : NULL;
}

int range_recorder_sensor_code(const char *name)
{
  for (int i = 0; name != NULL && i < RANGE_RECORDER_SENSOR_NB; i++) {
    if (strcmp(name, sensor_names[i]) == 0) {
      return i;
    }
  }
  return -1;
}

const char *range_recorder_class_name(uint8_t class_code)
{
  return wall_detector_class_name(class_code);
}

/** Microseconds as seconds with six decimals, exactly (no rounding through a double). */
static void format_time(char text[NUMBER_LEN], uint64_t t_us)
{
  snprintf(text, NUMBER_LEN, "%llu.%06u", (unsigned long long)(t_us / 1000000u), (unsigned)(t_us % 1000000u));
}

/** A float with the fewest significant digits (1 to 9) that read back as the same float; "" for NaN. */
static void format_float(char text[NUMBER_LEN], float value)
{
  text[0] = '\0';
  if (isnan(value)) {
    return;
  }
  for (int digits = 1; digits <= 9; digits++) {   /* 9 digits always read back as the same float */
    snprintf(text, NUMBER_LEN, "%.*g", digits, (double)value);
    if (strtof(text, NULL) == value) {
      return;
    }
  }
}

/** snprintf's result as a row length: 0 (and an empty row) when it did not fit. */
static size_t row_length(char *row, size_t len, int n)
{
  if (n < 0 || (size_t)n >= len) {
    if (len > 0) {
      row[0] = '\0';
    }
    return 0;
  }
  return (size_t)n;
}

size_t range_recorder_reading_row(char *row, size_t len, const struct range_recorder_reading *r)
{
  const char *sensor = range_recorder_sensor_name(r->sensor);
  if (sensor == NULL) {
    return row_length(row, len, -1);
  }
  char t[NUMBER_LEN], measured[NUMBER_LEN], peer[NUMBER_LEN] = "";
  format_time(t, r->t_us);
  format_float(measured, r->measured_m);
  if (r->sensor == RANGE_RECORDER_RANGING) {
    snprintf(peer, sizeof(peer), "%u", (unsigned)r->peer);
  }
  return row_length(row, len, snprintf(row, len, "%s,%u,%s,%s,%s\n", t, (unsigned)r->vehicle, sensor, peer,
                                       measured));
}

size_t range_recorder_decision_row(char *row, size_t len, const struct range_recorder_decision *d)
{
  if (d->sonar > RANGE_RECORDER_SONAR_LEFT) {
    return row_length(row, len, -1);
  }
  char t[NUMBER_LEN], measured[NUMBER_LEN], confidence[NUMBER_LEN];
  format_time(t, d->t_us);
  format_float(measured, d->measured_m);
  format_float(confidence, d->confidence);
  return row_length(row, len, snprintf(row, len, "%s,%u,%s,%s,%s,%s,%s\n", t, (unsigned)d->vehicle,
                                       sensor_names[d->sonar], measured, range_recorder_class_name(d->detector_class),
                                       confidence, range_recorder_class_name(d->baseline_class)));
}

int range_recorder_file_path(char *path, size_t len, const char *dir, const char *name, const char *pattern,
                             unsigned ac_id)
{
  if (len == 0) {
    return -1;
  }
  if (dir != NULL && dir[0] != '\0') {
    const int n = snprintf(path, len, "%s/%s_%u.csv", dir, name, ac_id);
    if (n < 0 || (size_t)n >= len) {
      path[0] = '\0';
      return -1;
    }
    return n;
  }
  path[0] = '\0';
  if (pattern == NULL || pattern[0] == '\0') {
    return 0;
  }
  static const char placeholder[] = "{ac_id}";
  const size_t placeholder_len = sizeof(placeholder) - 1;
  char id[NUMBER_LEN];
  snprintf(id, sizeof(id), "%u", ac_id);
  size_t n = 0;
  for (const char *p = pattern; *p != '\0';) {
    const char *piece = p;
    size_t piece_len = 1;
    if (strncmp(p, placeholder, placeholder_len) == 0) {
      piece = id;
      piece_len = strlen(id);
      p += placeholder_len;
    } else {
      p++;
    }
    if (n + piece_len >= len) {
      path[0] = '\0';
      return -1;
    }
    memcpy(path + n, piece, piece_len);
    n += piece_len;
  }
  path[n] = '\0';
  return (int)n;
}

uint64_t range_recorder_clock_us(struct range_recorder_clock *clock, uint32_t stamp_us)
{
  if (!clock->started) {
    clock->started = true;
    clock->latest_us = stamp_us;
    return stamp_us;
  }
  /* the signed difference to the latest stamp, modulo 2^32: the nearest time with these low 32 bits */
  const int64_t delta_us = (int32_t)(stamp_us - (uint32_t)clock->latest_us);
  if (delta_us < 0 && (uint64_t)(-delta_us) > clock->latest_us) {
    return stamp_us;   /* before the clock's zero: as given */
  }
  const uint64_t t_us = delta_us < 0 ? clock->latest_us - (uint64_t)(-delta_us) : clock->latest_us + (uint64_t)delta_us;
  if (t_us > clock->latest_us) {
    clock->latest_us = t_us;
  }
  return t_us;
}
