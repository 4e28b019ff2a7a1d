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
 * @file nps_range_log.h
 * Writer of the range log (shared/spec/range-log.md): one row per simulated reading, with its ground
 * truth and every fixed context value of struct nps_sensor_ctx as a ctx_ column, but ctx_vehicle: that is the
 * row's `vehicle` column.
 */

#ifndef NPS_RANGE_LOG_H
#define NPS_RANGE_LOG_H

#include "nps_sensor_model_ctx.h"

#include <stdbool.h>
#include <stdio.h>

struct nps_range_log {
  FILE *file;
  const char *path;
  char *buffer;   ///< the file's stdio buffer (nps_csv_fopen)
};

/** Create the file and write the header; -1 with errno set on failure. */
extern int nps_range_log_open(struct nps_range_log *log, const char *path);
/**
 * One reading. `peer` is the other copter's id for ranging, negative for a sonar; `measured` NAN when the
 * sensor reported nothing. Does nothing on a log that is not open. The row goes through nps_csv_write (to the
 * calling thread's spool if it uses one).
 */
extern void nps_range_log_write(struct nps_range_log *log, double t_s, unsigned vehicle, const char *sensor, int peer,
                                double true_range_m, double measured_m, const struct nps_sensor_ctx *ctx);
/** Flush and close; -1 with errno set if anything could not be written. */
extern int nps_range_log_close(struct nps_range_log *log);
/** Whether the log is written (else nps_range_log_write does nothing): readers need not compute its columns. */
static inline bool nps_range_log_is_open(const struct nps_range_log *log)
{
  return log->file != NULL;
}

#endif /* NPS_RANGE_LOG_H */
