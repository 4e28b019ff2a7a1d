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
 * @file nps_host_world.h
 * What the host simulates around the modules: every copter's flight model and the logs.
 */

#ifndef NPS_HOST_WORLD_H
#define NPS_HOST_WORLD_H

#include "nps_host_options.h"
#include "nps_host_threads.h"
#include "nps_fdm_finken.h"

#include <stdio.h>

struct nps_host_world {
  unsigned vehicles;
  struct nps_fdm_finken_params fdm_params;
  struct nps_fdm_finken_gains fdm_gains; ///< of fdm_params for the step of the last nps_host_world_step
  struct nps_fdm_finken_state *flight; ///< flight model of each copter
  FILE *poses;                        ///< poses.csv: t, vehicle, x, y, z, yaw
  char *poses_buffer;                 ///< its stdio buffer (nps_csv_fopen)
  unsigned pose_log_every;            ///< steps between two pose rows
  unsigned long step;
};

/** Set up the vehicles, their initial poses and the logs in opt->out_dir; -1 with a message on stderr. */
extern int nps_host_world_open(struct nps_host_world *w, const struct nps_host_options *opt);
/**
 * Flight-model step of every copter toward its guided command, then the simulator hooks, at time t_s; the
 * per-copter parts on `threads`. -1 if log rows were lost (out of memory).
 */
extern int nps_host_world_step(struct nps_host_world *w, struct nps_host_threads *threads, double t_s, double dt_s);
/** Flush and close the logs, free everything; -1 with a message if a log could not be written. */
extern int nps_host_world_close(struct nps_host_world *w);

#endif /* NPS_HOST_WORLD_H */
