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

#include <errno.h>
#include <math.h>

/** The fixed context slots, in the order of the ctx_ columns. */
#define NPS_RANGE_LOG_CTX_COLUMNS NPS_CTX_EXTRA0

int nps_range_log_open(struct nps_range_log *log, const char *path)
{
  log->path = path;
  log->file = fopen(path, "w");
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
  fprintf(log->file, "%.4f,%u,%s,", t_s, vehicle, sensor);
  if (peer >= 0) {
    fprintf(log->file, "%d", peer);
  }
  fprintf(log->file, ",%.4f,", true_range_m);
  if (!isnan(measured_m)) {
    fprintf(log->file, "%.4f", measured_m);
  }
  for (int slot = 0; slot < NPS_RANGE_LOG_CTX_COLUMNS; slot++) {
    const double v = nps_sensor_ctx_get(ctx, slot);
    fprintf(log->file, isnan(v) ? ",0" : ",%.6g", v);
  }
  fputc('\n', log->file);
}

int nps_range_log_close(struct nps_range_log *log)
{
  if (log->file == NULL) {
    return 0;
  }
  const int failed = ferror(log->file);
  const int closed = fclose(log->file);
  log->file = NULL;
  if (failed && errno == 0) {
    errno = EIO;
  }
  return (failed || closed != 0) ? -1 : 0;
}
