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

#include "generated/airframe.h"
#include "firmwares/rotorcraft/autopilot_guided.h"
#include "nps_fdm.h"
#include "pprz_host_vehicle.h"
#include "state.h"

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
#define NPS_POSE_LOG_FREQUENCY 10     ///< [Hz] rows per copter in poses.csv
#endif
#ifndef NPS_START_RADIUS
#define NPS_START_RADIUS 1.0          ///< [m] copters start evenly spaced on a circle of this radius
#endif

/** mkdir -p */
static int make_dirs(const char *path)
{
  char buf[4096];
  if (snprintf(buf, sizeof(buf), "%s", path) >= (int)sizeof(buf)) {
    errno = ENAMETOOLONG;
    return -1;
  }
  for (char *p = buf + 1; ; p++) {
    if (*p == '/' || *p == '\0') {
      const char saved = *p;
      *p = '\0';
      if (mkdir(buf, 0777) < 0 && errno != EEXIST) {
        return -1;
      }
      *p = saved;
      if (saved == '\0') {
        return 0;
      }
    }
  }
}

static FILE *open_log(const char *dir, const char *name, const char *header)
{
  char path[4096];
  snprintf(path, sizeof(path), "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  if (f == NULL) {
    fprintf(stderr, "error: cannot write %s: %s\n", path, strerror(errno));
    return NULL;
  }
  fputs(header, f);
  return f;
}

/** Copy the flight model of the current vehicle into NPS's fdm and Paparazzi's state (ENU -> NED). */
static void publish_state(const struct nps_fdm_finken_state *s, double t_s)
{
  struct NpsFdm *f = nps_fdm_current();
  f->time = t_s;
  f->ltpprz_pos = (struct NedCoor_d) { s->pos_m[1], s->pos_m[0], -s->pos_m[2] };
  f->ltpprz_ecef_vel = (struct NedCoor_d) { s->vel_mps[1], s->vel_mps[0], -s->vel_mps[2] };
  f->ltpprz_to_body_eulers = (struct DoubleEulers) { 0.0, 0.0, M_PI / 2.0 - s->yaw_rad };
  f->body_ecef_rotvel = (struct DoubleRates) { 0.0, 0.0, -s->yaw_rate_rps };
  f->agl = s->pos_m[2];
  f->on_ground = s->pos_m[2] <= 0.0;

  struct State *st = state_current();
  st->enu_pos_f = (struct EnuCoor_f) { (float)s->pos_m[0], (float)s->pos_m[1], (float)s->pos_m[2] };
  st->ned_pos_f = (struct NedCoor_f) { (float)s->pos_m[1], (float)s->pos_m[0], (float)-s->pos_m[2] };
  st->enu_speed_f = (struct EnuCoor_f) { (float)s->vel_mps[0], (float)s->vel_mps[1], (float)s->vel_mps[2] };
  st->ned_speed_f = (struct NedCoor_f) { (float)s->vel_mps[1], (float)s->vel_mps[0], (float)-s->vel_mps[2] };
  st->ned_to_body_eulers_f = (struct FloatEulers) { 0.0f, 0.0f, (float)(M_PI / 2.0 - s->yaw_rad) };
  st->body_rates_f = (struct FloatRates) { 0.0f, 0.0f, (float)-s->yaw_rate_rps };
}

int nps_host_world_open(struct nps_host_world *w, const struct nps_host_options *opt)
{
  memset(w, 0, sizeof(*w));
  w->vehicles = opt->vehicles;
  w->fdm_params = (struct nps_fdm_finken_params) {
    .velocity_tau_s = NPS_FINKEN_VELOCITY_TAU, .yaw_tau_s = NPS_FINKEN_YAW_TAU,
    .altitude_m = NPS_FINKEN_ALTITUDE, .altitude_tau_s = NPS_FINKEN_ALTITUDE_TAU,
    .max_speed_mps = NPS_FINKEN_MAX_SPEED,
  };
  w->pose_log_every = (unsigned)fmax(1.0, round(PERIODIC_FREQUENCY / (double)NPS_POSE_LOG_FREQUENCY));
  w->flight = calloc(opt->vehicles, sizeof(*w->flight));
  if (w->flight == NULL) {
    fprintf(stderr, "error: out of memory for %u flight models\n", opt->vehicles);
    return -1;
  }
  if (make_dirs(opt->out_dir) < 0) {
    fprintf(stderr, "error: cannot create %s: %s\n", opt->out_dir, strerror(errno));
    free(w->flight);
    return -1;
  }
  w->poses = open_log(opt->out_dir, "poses.csv", "t,vehicle,x,y,z,yaw\n");
  if (w->poses == NULL) {
    free(w->flight);
    return -1;
  }
  pprz_vehicles_setup(opt->vehicles, NULL);
  for (unsigned v = 0; v < opt->vehicles; v++) {
    struct nps_fdm_finken_state *s = &w->flight[v];
    const double angle = 2.0 * M_PI * v / opt->vehicles;
    s->pos_m[0] = NPS_START_RADIUS * cos(angle);
    s->pos_m[1] = NPS_START_RADIUS * sin(angle);
    s->pos_m[2] = NPS_FINKEN_ALTITUDE;
    s->yaw_rad = angle;
    pprz_vehicle_select(v);
    publish_state(s, 0.0);
  }
  return 0;
}

void nps_host_world_step(struct nps_host_world *w, double t_s, double dt_s)
{
  const bool log_poses = (w->step++ % w->pose_log_every) == 0;
  for (unsigned v = 0; v < w->vehicles; v++) {
    pprz_vehicle_select(v);
    struct nps_fdm_finken_state *s = &w->flight[v];
    const struct autopilot_guided_command *cmd = autopilot_guided_current();
    /* guided commands are NED (north, east, heading from north); the flight model is ENU */
    const double vx = cmd->active ? cmd->vy : 0.0, vy = cmd->active ? cmd->vx : 0.0;
    const double yaw = cmd->active ? M_PI / 2.0 - cmd->heading : s->yaw_rad;
    nps_fdm_finken_step(s, &w->fdm_params, vx, vy, yaw, dt_s);
    publish_state(s, t_s);
    if (log_poses) {
      fprintf(w->poses, "%.4f,%u,%.4f,%.4f,%.4f,%.4f\n", t_s, pprz_vehicle_ac_id(), s->pos_m[0], s->pos_m[1],
              s->pos_m[2], s->yaw_rad);
    }
  }
}

int nps_host_world_close(struct nps_host_world *w)
{
  int rc = 0;
  if (ferror(w->poses) || fclose(w->poses) != 0) {
    fprintf(stderr, "error: writing poses.csv failed: %s\n", strerror(errno));
    rc = -1;
  }
  free(w->flight);
  pprz_vehicles_teardown();
  return rc;
}
