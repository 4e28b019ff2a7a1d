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
 * @file nps_range_log.c
 * Writer of the range log (see nps_range_log.h).
 */

#include "nps_range_log.h"
#include "nps_csv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

/** The fixed context slots, in the order of the ctx_ columns: all before ctx_vehicle, which is the vehicle column. */
#define NPS_RANGE_LOG_CTX_COLUMNS NPS_CTX_VEHICLE
/** Characters of the sensor name kept (range-log names are at most "sonar_front"). */
#define NPS_RANGE_LOG_SENSOR_MAX 24
/** Longest row: the sensor name, and t, vehicle, peer, true range, reading and the contexts as numbers. */
#define NPS_RANGE_LOG_ROW_LEN (NPS_RANGE_LOG_SENSOR_MAX + (6 + NPS_RANGE_LOG_CTX_COLUMNS) * (NPS_CSV_NUMBER_LEN + 1))

int nps_range_log_open(struct nps_range_log *log, const char *path)
{
  log->path = path;
  log->file = nps_csv_fopen(path, &log->buffer);
  if (log->file == NULL) {
    return -1;
  }
  fputs("t,vehicle,sensor,peer,true_range,measured", log->file);
  for (int slot = 0; slot < NPS_RANGE_LOG_CTX_COLUMNS; slot++) {
    fprintf(log->file, ",%s", nps_sensor_ctx_fixed_name(slot));
  }
  fputc('\n', log->file);
  return 0;
}

void nps_range_log_write(struct nps_range_log *log, double t_s, unsigned vehicle, const char *sensor, int peer,
                         double true_range_m, double measured_m, const struct nps_sensor_ctx *ctx)
{
  if (log->file == NULL) {
    return;
  }
  char row[NPS_RANGE_LOG_ROW_LEN];
  char *p = row;
  p += nps_csv_fixed4(p, t_s);
  *p++ = ',';
  p += nps_csv_int(p, (long)vehicle);
  *p++ = ',';
  for (const char *c = sensor; *c != '\0' && p < row + NPS_RANGE_LOG_SENSOR_MAX; c++) {
    *p++ = *c;
  }
  *p++ = ',';
  if (peer >= 0) {
    p += nps_csv_int(p, peer);
  }
  *p++ = ',';
  p += nps_csv_fixed4(p, true_range_m);
  *p++ = ',';
  if (!isnan(measured_m)) {
    p += nps_csv_fixed4(p, measured_m);
  }
  for (int slot = 0; slot < NPS_RANGE_LOG_CTX_COLUMNS; slot++) {
    const double v = nps_sensor_ctx_get(ctx, slot);
    *p++ = ',';
    p += nps_csv_g9(p, isnan(v) ? 0.0 : v);
  }
  *p++ = '\n';
  nps_csv_write(log->file, row, (size_t)(p - row));
}

int nps_range_log_close(struct nps_range_log *log)
{
  if (log->file == NULL) {
    return 0;
  }
  const int failed = ferror(log->file);
  const int closed = fclose(log->file);
  log->file = NULL;
  free(log->buffer);
  log->buffer = NULL;
  if (failed && errno == 0) {
    errno = EIO;
  }
  return (failed || closed != 0) ? -1 : 0;
}
