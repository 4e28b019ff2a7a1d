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
 * @file modules/range_recorder/range_recorder.h
 * Paparazzi module: records every sonar reading, every ranging distance and every wall-detector decision, to two
 * CSV files (formats in range_recorder_rows.h) and as pprzlink telemetry (FINKEN_RANGE_READING,
 * FINKEN_WALL_DECISION: range_recorder_telemetry.h), so that Paparazzi's server logs them.
 *
 * Inputs (ABI): OBSTACLE_DETECTION from sonar_array's horizontal sonars (senders SONAR_ARRAY_FRONT_ID ..
 * SONAR_ARRAY_LEFT_ID; other senders are ignored), AGL from its downward sonar (SONAR_ARRAY_DOWN_ID),
 * RANGING_DISTANCE and WALL_DETECTION. The defines (RANGE_RECORDER_*) are listed with their defaults in
 * range_recorder.c and conf/modules/range_recorder.xml.
 *
 * Files: written through stdio's buffer, flushed every RANGE_RECORDER_FLUSH_PERIOD by the periodic task and closed
 * at exit (atexit) or by range_recorder_close(). An error (a file that cannot be opened or written) is reported
 * once on stderr and ends that file's recording; the flight goes on.
 */

#ifndef RANGE_RECORDER_H
#define RANGE_RECORDER_H

#include "std.h"
#include "modules/core/abi.h"
#include "modules/multi_vehicle/vehicle_local.h"
#include "modules/range_recorder/range_recorder_rows.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Longest path of a file, its NUL included. */
#define RANGE_RECORDER_PATH_LEN 1024

/** One of the recorder's files. */
struct range_recorder_file {
  FILE *f;                              ///< NULL: not recording to it (off, never opened, or failed)
  uint32_t rows;                        ///< rows written to it (header not counted)
  char path[RANGE_RECORDER_PATH_LEN];   ///< its path, for the messages
};

/** Module state of one copter. */
struct range_recorder {
  struct range_recorder_file readings;    ///< every reading: t,vehicle,sensor,peer,measured
  struct range_recorder_file decisions;   ///< every wall-detector decision
  struct range_recorder_clock clock;      ///< the 64-bit clock of the rows' t
  uint32_t flushed_us;                    ///< when the files were last flushed [us]
  abi_event obstacle_ev, agl_ev, ranging_ev, wall_ev;
};

VEHICLE_LOCAL_DECLARE(struct range_recorder, range_recorder);

/** Module init: ABI bindings, the files from the defines and $RANGE_RECORDER_OUT_ENV. */
extern void range_recorder_init(void);

/** Periodic task: flushes the files every RANGE_RECORDER_FLUSH_PERIOD. */
extern void range_recorder_periodic(void);

/**
 * Record to the files at these paths from now on (each with its header; NULL or "": that file off), after closing
 * any open ones. Returns 0, or -1 when one could not be opened (reported on stderr; that file stays off).
 */
extern int range_recorder_open(const char *readings_path, const char *decisions_path);

/** Flush and close the files (each error reported on stderr); returns 0, or -1 when a write failed. */
extern int range_recorder_close(void);

#ifdef __cplusplus
}
#endif

#endif /* RANGE_RECORDER_H */
