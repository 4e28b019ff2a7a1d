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
 * @file nps_host_options.h
 * Command line of the NPS-style host.
 */

#ifndef NPS_HOST_OPTIONS_H
#define NPS_HOST_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>

#include "nps_ins_drift.h"

struct nps_host_options {
  unsigned vehicles;      ///< number of copters
  uint64_t seed;          ///< seed of every random stream
  double duration_s;      ///< simulated time [s]
  const char *out_dir;    ///< where the logs go
  bool realtime;          ///< pace the simulation to the wall clock
  bool quiet;             ///< no progress display
  bool no_logs;           ///< write no logs (batch runs that only need the modules' behaviour)
  const char *ranging_replay; ///< candump log fed to the copters' ranging instead of simulated ranging, or NULL
  const char *arena_file;   ///< arena XML, NULL: the airframe's NPS_ARENA_FILE
  const char *sensor_model; ///< sensor model file or inline text, NULL: the airframe's NPS_SENSOR_MODEL
  unsigned threads;         ///< threads of the modules phase, 0: nps_host_threads_default
  struct nps_ins_drift_params ins_drift; ///< drift of the copters' position estimates (sd 0: none)
  double pose_rate_hz;      ///< rows per copter and second of poses.csv, 0: the airframe's NPS_POSE_LOG_FREQUENCY
                            ///< (checked against the step rate by nps_host_world_open)
};

/** Parse argv: 0 to run, 1 after printing the usage for --help, -1 (reason and usage on stderr) on a bad option. */
extern int nps_host_parse_options(int argc, char **argv, struct nps_host_options *opt);

#endif /* NPS_HOST_OPTIONS_H */
