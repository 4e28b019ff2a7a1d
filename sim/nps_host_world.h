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
 *
 * A host step at time t: nps_host_world_step (the simulator's world step, on one thread: the copters take the
 * poses their flight models reached, contacts, walls), then for each copter, on any thread, in this order:
 * nps_host_world_publish (its flight model takes the contact-corrected position; its modules read their state from
 * the flight model, state.h), its modules, nps_host_world_advance (its flight model one step on toward the command
 * the modules just gave; the simulator takes the pose at the next nps_host_world_step). Before the first step every
 * copter advances once from its start pose.
 */

#ifndef NPS_HOST_WORLD_H
#define NPS_HOST_WORLD_H

#include "nps_host_options.h"
#include "nps_finken_lag.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

struct nps_host_world {
  unsigned vehicles;
  struct nps_finken_lag_params fdm_params;
  struct nps_finken_lag_gains fdm_gains; ///< of fdm_params for the host step
  struct nps_finken_lag_state *flight; ///< flight model of each copter
  struct nps_ins_drift_params drift_params; ///< drift of the position estimates (sd 0: none)
  struct nps_ins_drift *drift;        ///< drift of each copter's estimate, NULL without drift
  double dt_s;                        ///< step [s]
  FILE *poses;                        ///< poses.csv: t, vehicle, x, y, z, yaw, qx, qy, qz, qw
  char *poses_buffer;                 ///< its stdio buffer (nps_csv_fopen)
  bool speed_needed;                  ///< the simulator reads the copters' speeds (nps_swarm_needs_speed)
  unsigned pose_log_every;            ///< steps between two pose rows
  double pose_rate_hz;                ///< pose rows per copter and second (the step rate / pose_log_every)
  unsigned long step;
  double t_s;                         ///< time of the current step [s]
};

/** Set up the vehicles, their initial poses and the logs in opt->out_dir, for steps of dt_s; -1 with a message on stderr. */
extern int nps_host_world_open(struct nps_host_world *w, const struct nps_host_options *opt, double dt_s);
/** The simulator's world step at time t_s (one thread); whether the copters' poses are logged in this step. */
extern bool nps_host_world_step(struct nps_host_world *w, double t_s);
/** Copter v (selected here) takes its contact-corrected position, which its modules then read (state.h);
 * its pose row if log_poses (on a worker thread: to its spool). */
extern void nps_host_world_publish(struct nps_host_world *w, unsigned v, bool log_poses);
/** Copter v's flight model (v selected here) one step toward its guided command; its pose to the simulator. */
extern void nps_host_world_advance(struct nps_host_world *w, unsigned v);
/** Flush and close the logs, free everything; -1 with a message if a log could not be written. */
extern int nps_host_world_close(struct nps_host_world *w);
/** The staged path of a log that failed to be written so far, NULL while every write succeeded. */
extern const char *nps_host_world_write_error(const struct nps_host_world *w);
/** About how many bytes of logs a simulated second writes (0 without logs), for the free-space check. */
extern uint64_t nps_host_world_log_bytes_per_s(const struct nps_host_world *w);

#endif /* NPS_HOST_WORLD_H */
