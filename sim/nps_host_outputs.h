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
 * @file nps_host_outputs.h
 * The files a host run writes in its --out folder, so that none is ever lost or torn: each is written under a staged
 * name (OUT/.NAME.partial) and they are put in place together when the run ends (completed, stopped by a signal or by
 * a write error), cut after their last complete row. A run that fails to start leaves the previous run's files
 * byte for byte.
 */

#ifndef NPS_HOST_OUTPUTS_H
#define NPS_HOST_OUTPUTS_H

#include <stdint.h>

/** The files of a run (a file of an earlier run that this run does not write is removed when it ends). */
#define NPS_HOST_OUTPUT_NAMES { "readings.csv", "poses.csv", "walls.csv", "detections.csv", "ranging_replay.csv" }

/** Create the folder and forget staged files of a run that was killed; -1 with the reason on stderr. */
extern int nps_host_outputs_begin(const char *out_dir);
/** The staged path of output `name` (one of NPS_HOST_OUTPUT_NAMES), valid until the run ends. */
extern const char *nps_host_outputs_staged(const char *name);
/**
 * Whether `bytes` more fit in the folder's file system (with 5 % to spare); if not, says so on stderr, naming the
 * folder and both sizes.
 */
extern int nps_host_outputs_fit(uint64_t bytes);
/** Put every staged file in place, cut after its last complete row; -1 (reason on stderr) if one could not be. */
extern int nps_host_outputs_commit(void);
/** Remove the staged files (a run that did not start); the previous run's files stay as they were. */
extern void nps_host_outputs_discard(void);

#endif /* NPS_HOST_OUTPUTS_H */
