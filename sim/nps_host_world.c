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
 * @file nps_host_world.c
 * Flight models and logs of the host (see nps_host_world.h).
 */

#include "nps_host_world.h"
#include "nps_host_detections.h"
#include "nps_host_outputs.h"

#include "generated/airframe.h"
#include "firmwares/rotorcraft/autopilot_guided.h"
#include "nps_csv.h"
#include "nps_run_log.h"
#include "nps_arena_start.h"
#include "nps_fdm.h"
#include "nps_swarm.h"
#include "pprz_host_vehicle.h"
#include "state_host.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Flight model parameters: a <section name="SIMULATOR" prefix="NPS_"> of the airframe may override them. */
#ifndef NPS_FINKEN_VELOCITY_TAU
#define NPS_FINKEN_VELOCITY_TAU 0.5   ///< [s] time constant of the velocity response
#endif
#ifndef NPS_FINKEN_YAW_TAU
#define NPS_FINKEN_YAW_TAU 0.3        ///< [s] time constant of the heading response
#endif
#ifndef NPS_FINKEN_ALTITUDE
#define NPS_FINKEN_ALTITUDE 0.6       ///< [m] the FINken's flight height in the arena (report, section 2.1)
#endif
#ifndef NPS_FINKEN_ALTITUDE_TAU
#define NPS_FINKEN_ALTITUDE_TAU 0.5   ///< [s] time constant of the altitude hold
#endif
#ifndef NPS_FINKEN_MAX_SPEED
#define NPS_FINKEN_MAX_SPEED 1.0      ///< [m/s] horizontal speed limit
#endif
#ifndef NPS_POSE_LOG_FREQUENCY
#define NPS_POSE_LOG_FREQUENCY 10     ///< [Hz] rows per copter in poses.csv (--pose-rate overrides)
#endif
#ifndef NPS_ARENA_FILE
#define NPS_ARENA_FILE "conf/arena/swarmlab.xml"                 ///< arena and curtain walls
#endif
#ifndef NPS_SENSOR_MODEL
#define NPS_SENSOR_MODEL "conf/sensor_models/finken_default.xml" ///< sensor model file or inline model
#endif
#ifndef NPS_WALLS_SNAPSHOT_PERIOD
#define NPS_WALLS_SNAPSHOT_PERIOD 1.0  ///< [s] between two rows per wall segment in walls.csv
#endif

/** Mean size of a row of poses.csv [bytes] (measured in the example airframe's logs), for the free-space check. */
#define NPS_HOST_POSE_ROW_BYTES 60.0

/** The world whose flight models NPS's fdm shows (fill_fdm); one per host process. */
static const struct nps_host_world *fdm_world;

/**
 * NPS's fdm of copter v (ENU -> NED), when read (nps_fdm_set_source): its flight model as published this step,
 * since a copter's modules run between its publish and its next flight model step (nps_host_world.h).
 */
static void fill_fdm(struct NpsFdm *f, unsigned v)
{
  const struct nps_finken_lag_state *s = &fdm_world->flight[v];
  f->time = fdm_world->t_s;
  f->ltpprz_pos = (struct NedCoor_d) { s->pos_m[1], s->pos_m[0], -s->pos_m[2] };
  f->ltpprz_ecef_vel = (struct NedCoor_d) { s->vel_mps[1], s->vel_mps[0], -s->vel_mps[2] };
  f->ltpprz_to_body_eulers = (struct DoubleEulers) { 0.0, 0.0, M_PI / 2.0 - s->yaw_rad };
  /* the same heading psi as Paparazzi's NED -> body FRD quaternion (qi scalar): a turn by psi about down */
  const double half_psi = 0.5 * f->ltpprz_to_body_eulers.psi;
  f->ltpprz_to_body_quat = (struct DoubleQuat) { cos(half_psi), 0.0, 0.0, sin(half_psi) };
  f->body_ecef_rotvel = (struct DoubleRates) { 0.0, 0.0, -s->yaw_rate_rps };
  f->agl = s->pos_m[2];
  f->on_ground = s->pos_m[2] <= 0.0;
}

/** The drift of every copter's position estimate (--ins-drift), none with sd 0; -1 with a message. */
static int start_drift(struct nps_host_world *w, const struct nps_host_options *opt)
{
  w->drift_params = opt->ins_drift;
  if (!(opt->ins_drift.sd_mps > 0.0)) {
    return 0;
  }
  w->drift = calloc(opt->vehicles, sizeof(*w->drift));
  if (w->drift == NULL) {
    fprintf(stderr, "error: out of memory for the INS drift of %u copters\n", opt->vehicles);
    return -1;
  }
  for (unsigned v = 0; v < opt->vehicles; v++) {
    pprz_vehicle_select(v);
    if (nps_ins_drift_init(&w->drift[v], &w->drift_params, opt->seed, pprz_vehicle_ac_id()) < 0) {
      fprintf(stderr, "error: out of memory for the INS drift of %u copters\n", opt->vehicles);
      return -1;
    }
  }
  return 0;
}

/**
 * Steps between two rows of poses.csv at the step rate step_hz: --pose-rate when given, which must be step_hz
 * divided by a whole number (else -1 with the reason and the nearest rates that are), else the airframe's
 * NPS_POSE_LOG_FREQUENCY rounded to whole steps.
 */
static int pose_log_every(const struct nps_host_options *opt, double step_hz, unsigned *every)
{
  if (!(opt->pose_rate_hz > 0.0)) {
    *every = (unsigned)fmax(1.0, round(step_hz / (double)NPS_POSE_LOG_FREQUENCY));
    return 0;
  }
  const double ratio = step_hz / opt->pose_rate_hz, steps = round(ratio);
  if (ratio < 1.0 - 1e-9) {
    fprintf(stderr, "error: --pose-rate %g Hz is above the step rate of %g Hz (the airframe's PERIODIC_FREQUENCY): "
            "at most one pose row per step, i.e. up to %g Hz\n", opt->pose_rate_hz, step_hz, step_hz);
    return -1;
  }
  if (fabs(ratio - steps) > 1e-9 * ratio || steps > 1e9) {
    const double fewer = ceil(ratio), more = floor(ratio);
    fprintf(stderr, "error: --pose-rate %g Hz: pose rows are logged a whole number of steps apart and the host steps "
            "at %g Hz (the airframe's PERIODIC_FREQUENCY), so %g Hz is %g steps apart; the nearest rates it can log "
            "are %.6g Hz (every %.0f steps) and %.6g Hz (every %.0f steps)\n", opt->pose_rate_hz, step_hz,
            opt->pose_rate_hz, ratio, step_hz / fewer, fewer, step_hz / more, more);
    return -1;
  }
  *every = (unsigned)steps;
  return 0;
}

/** Put every copter at its start (nps_arena_start.h), Paparazzi's state with it. */
static int start_copters(struct nps_host_world *w, const struct nps_host_options *opt, const char *arena_file)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN] = "out of memory";
  double (*start_m)[2] = malloc(opt->vehicles * sizeof(*start_m));
  double *yaw_rad = malloc(opt->vehicles * sizeof(*yaw_rad));
  const int rc = start_m != NULL && yaw_rad != NULL ?
                 nps_arena_start_poses(nps_swarm_arena(), opt->vehicles, start_m, yaw_rad, err, sizeof(err)) : -1;
  if (rc < 0) {
    fprintf(stderr, "error: %s: %s\n", arena_file, err);
  }
  for (unsigned v = 0; rc == 0 && v < opt->vehicles; v++) {
    struct nps_finken_lag_state *s = &w->flight[v];
    s->pos_m[0] = start_m[v][0];
    s->pos_m[1] = start_m[v][1];
    s->pos_m[2] = NPS_FINKEN_ALTITUDE;
    s->yaw_rad = yaw_rad[v];
    pprz_vehicle_select(v);
    /* Paparazzi's state follows it when read, with the estimate's drift (state.h) */
    state_follow_flight_model(state_current(), s, w->drift != NULL ? w->drift[v].pos_error_m : NULL);
    nps_swarm_set_pose(v, s->pos_m, s->yaw_rad, 0.0);
  }
  free(start_m);
  free(yaw_rad);
  return rc;
}

int nps_host_world_open(struct nps_host_world *w, const struct nps_host_options *opt, double dt_s)
{
  memset(w, 0, sizeof(*w));
  w->vehicles = opt->vehicles;
  w->dt_s = dt_s;
  w->fdm_params = (struct nps_finken_lag_params) {
    .velocity_tau_s = NPS_FINKEN_VELOCITY_TAU, .yaw_tau_s = NPS_FINKEN_YAW_TAU,
    .altitude_m = NPS_FINKEN_ALTITUDE, .altitude_tau_s = NPS_FINKEN_ALTITUDE_TAU,
    .max_speed_mps = NPS_FINKEN_MAX_SPEED,
  };
  nps_finken_lag_gains_init(&w->fdm_gains, &w->fdm_params, dt_s);
  if (pose_log_every(opt, PERIODIC_FREQUENCY, &w->pose_log_every) < 0) {
    return -1;
  }
  w->pose_rate_hz = PERIODIC_FREQUENCY / (double)w->pose_log_every;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  const char *poses_path = nps_host_outputs_staged("poses.csv");
  const char *readings_path = nps_host_outputs_staged("readings.csv");
  const char *walls_path = nps_host_outputs_staged("walls.csv");
  const struct nps_swarm_config swarm = {
    .seed = opt->seed, .vehicles = opt->vehicles, .arena_file = opt->arena_file ? opt->arena_file : NPS_ARENA_FILE,
    .sensor_model = opt->sensor_model ? opt->sensor_model : NPS_SENSOR_MODEL,
    .readings_path = opt->no_logs ? NULL : readings_path, .walls_path = opt->no_logs ? NULL : walls_path,
    .walls_period_s = NPS_WALLS_SNAPSHOT_PERIOD,
  };
  if (nps_swarm_init(&swarm, err, sizeof(err)) < 0) {
    fprintf(stderr, "error: %s\n", err);
    return -1;
  }
  const struct nps_arena *arena = nps_swarm_arena();
  if (!nps_arena_height_fits(arena->copter_height_m, arena->wall_height_m, NPS_FINKEN_ALTITUDE)) {
    const double half_m = 0.5 * arena->copter_height_m;
    fprintf(stderr, "error: the airframe's FINKEN_ALTITUDE (NPS_FINKEN_ALTITUDE) = %g m: copters %g m tall fly "
            "between the floor and the wall top of %s only above %g m and up to %g m\n", (double)NPS_FINKEN_ALTITUDE,
            arena->copter_height_m, swarm.arena_file, half_m, arena->wall_height_m - half_m);
    nps_swarm_free();
    return -1;
  }
  w->speed_needed = nps_swarm_needs_speed();
  w->flight = calloc(opt->vehicles, sizeof(*w->flight));
  w->poses = opt->no_logs ? NULL : nps_csv_fopen(poses_path, &w->poses_buffer);
  if (w->flight == NULL || (w->poses == NULL && !opt->no_logs)) {
    fprintf(stderr, "error: cannot write %s: %s\n", poses_path, strerror(errno));
    if (w->poses != NULL) {
      fclose(w->poses);
    }
    free(w->poses_buffer);
    free(w->flight);
    nps_swarm_free();
    return -1;
  }
  pprz_vehicles_setup(opt->vehicles, NULL);
  fdm_world = w;
  nps_fdm_set_source(fill_fdm);
  if (!opt->no_logs) {
    fputs(NPS_POSE_LOG_HEADER, w->poses);
    nps_host_detections_start(nps_host_outputs_staged("detections.csv"));
  }
  if (start_drift(w, opt) < 0) {
    nps_host_world_close(w);
    return -1;
  }
  if (start_copters(w, opt, swarm.arena_file) < 0) {
    nps_host_world_close(w);
    return -1;
  }
  nps_swarm_step(0.0);
  return 0;
}

/**
 * Take copter v's contact-corrected position (nps_finken_lag_take_contact). Out of line, as log_pose: the common
 * publish, which needs neither, then needs no stack frame.
 */
static __attribute__((noinline)) void apply_contact(struct nps_finken_lag_state *s, unsigned v)
{
  double pos_m[3];
  nps_swarm_get_position(v, pos_m);
  if (pos_m[0] != s->pos_m[0] || pos_m[1] != s->pos_m[1]) {   /* else no contact moved it (pushed back and forth) */
    nps_finken_lag_take_contact(s, pos_m);
  }
}

/**
 * One row of poses.csv: t, vehicle, x, y, z, yaw and the attitude quaternion (the current vehicle). The host's
 * flight model (nps_finken_lag.h) hovers level and turns about z alone: no roll, no pitch, so the quaternion is
 * the heading's, (0, 0, sin(yaw/2), cos(yaw/2)).
 */
static __attribute__((noinline)) void log_pose(FILE *poses, const struct nps_finken_lag_state *s, double t_s)
{
  char row[NPS_POSE_LOG_ROW_LEN];
  double q[4];
  nps_pose_quat_of_yaw(s->yaw_rad, q);
  const size_t len = nps_pose_log_row(row, t_s, pprz_vehicle_ac_id(), s->pos_m, s->yaw_rad, q);
  nps_csv_write(poses, row, len);   /* a worker thread's spool: appended in copter order */
}

void nps_host_world_advance(struct nps_host_world *w, unsigned v)
{
  pprz_vehicle_select(v);
  struct nps_finken_lag_state *s = &w->flight[v];
  const struct autopilot_guided_command *cmd = autopilot_guided_current();
  /* guided commands are NED (north, east, heading from north); the flight model is ENU */
  const double vx = cmd->active ? cmd->vy : 0.0, vy = cmd->active ? cmd->vx : 0.0;
  const double yaw = cmd->active ? M_PI / 2.0 - cmd->heading : s->yaw_rad;
  nps_finken_lag_advance(s, &w->fdm_params, &w->fdm_gains, vx, vy, yaw);
  if (w->drift != NULL) {
    nps_ins_drift_step(&w->drift[v], &w->drift_params, w->dt_s);
  }
  /* the speed only when a reading uses it (no hypot call: speeds in m/s neither overflow nor underflow squared) */
  const double speed_mps = w->speed_needed ? sqrt(s->vel_mps[0] * s->vel_mps[0] + s->vel_mps[1] * s->vel_mps[1]) : 0.0;
  nps_swarm_set_pose(v, s->pos_m, s->yaw_rad, speed_mps);
}

bool nps_host_world_step(struct nps_host_world *w, double t_s)
{
  w->t_s = t_s;
  nps_swarm_step(t_s);
  return w->poses != NULL && (w->step++ % w->pose_log_every) == 0;
}

void nps_host_world_publish(struct nps_host_world *w, unsigned v, bool log_poses)
{
  pprz_vehicle_select(v);
  struct nps_finken_lag_state *s = &w->flight[v];
  if (nps_swarm_pushed(v)) {   /* else the simulator's position is the flight model's, which it was given */
    apply_contact(s, v);
  }
  if (log_poses) {
    log_pose(w->poses, s, w->t_s);
  }
}

const char *nps_host_world_write_error(const struct nps_host_world *w)
{
  if (w->poses != NULL && ferror(w->poses)) {
    return nps_host_outputs_staged("poses.csv");
  }
  const char *failed = nps_swarm_write_error();
  return failed != NULL ? failed : nps_host_detections_write_error();
}

uint64_t nps_host_world_log_bytes_per_s(const struct nps_host_world *w)
{
  if (w->poses == NULL) {
    return 0;
  }
  /* row sizes measured in logs of the example airframe; sonar rows: 5 sonars at 20 Hz, poses at their rate,
   * ranging 10 Hz per pair within the radio horizon at the start, detections 4 sonars at 20 Hz, walls one row per
   * plate and period */
  const struct nps_arena *a = nps_swarm_arena();
  return (uint64_t)(w->vehicles * (100.0 * 71 + w->pose_rate_hz * NPS_HOST_POSE_ROW_BYTES + 80.0 * 57)
                    + nps_swarm_ranging_pairs_in_horizon() * 10.0 * 68 + a->num_segments * 42.0 / NPS_WALLS_SNAPSHOT_PERIOD);
}

int nps_host_world_close(struct nps_host_world *w)
{
  int rc = 0;
  if (w->poses != NULL && (ferror(w->poses) | fclose(w->poses)) != 0) {
    fprintf(stderr, "error: writing %s failed: %s\n", nps_host_outputs_staged("poses.csv"), strerror(errno));
    rc = -1;
  }
  if (nps_host_detections_stop() < 0) {
    fprintf(stderr, "error: writing %s failed: %s\n", nps_host_outputs_staged("detections.csv"), strerror(errno));
    rc = -1;
  }
  const char *failed = nps_swarm_write_error();
  if (nps_swarm_free() < 0) {
    fprintf(stderr, "error: writing %s failed: %s\n",
            failed != NULL ? failed : nps_host_outputs_staged("readings.csv"), strerror(errno));
    rc = -1;
  }
  free(w->poses_buffer);
  free(w->flight);
  if (w->drift != NULL) {
    for (unsigned v = 0; v < w->vehicles; v++) {
      nps_ins_drift_free(&w->drift[v]);
    }
    free(w->drift);
  }
  nps_fdm_set_source(NULL);
  fdm_world = NULL;
  pprz_vehicles_teardown();
  return rc;
}
