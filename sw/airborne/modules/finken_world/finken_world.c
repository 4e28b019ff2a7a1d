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
 * @file modules/finken_world/finken_world.c
 * The FINken arena inside Paparazzi's NPS (see finken_world.h).
 *
 * Files: FINKEN_WORLD_ARENA and FINKEN_WORLD_SENSOR_MODEL are read relative to $PAPARAZZI_HOME when they are
 * relative paths (the overlay puts ours under conf/). Logs: when the environment variable FINKEN_WORLD_OUT names
 * a directory, readings_<AC_ID>.csv (range-log format) and walls_<AC_ID>.csv are written there. When
 * FINKEN_WORLD_DURATION holds a number of seconds, the process ends (exit status 0, logs closed) once the
 * simulated time reaches it: NPS itself runs until it is stopped.
 */

#include "modules/finken_world/finken_world.h"

#include "mcu_periph/sys_time.h"
#include "nps_fdm.h"
#include "nps_sensor_model.h"   /* NPS_SENSOR_MODEL_ERR_LEN */
#include "nps_swarm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef PPRZ_HOST_MULTI_VEHICLE   /* our host's tests: the stand-ins' aircraft id */
#include "pprz_host_vehicle.h"
#define FINKEN_WORLD_AC_ID pprz_vehicle_ac_id()
#else
#include "generated/airframe.h"  /* AC_ID and the airframe's FINKEN_WORLD section */
#define FINKEN_WORLD_AC_ID AC_ID
#endif

#ifndef FINKEN_WORLD_ARENA
#define FINKEN_WORLD_ARENA "conf/arena/swarmlab.xml"          ///< arena and curtain walls (XML)
#endif
#ifndef FINKEN_WORLD_SENSOR_MODEL
#define FINKEN_WORLD_SENSOR_MODEL "conf/sensor_models/finken_default.xml" ///< model file or one-line model
#endif
#ifndef FINKEN_WORLD_SEED
#define FINKEN_WORLD_SEED 1            ///< seed of every random stream (each aircraft's streams follow from AC_ID)
#endif
#ifndef FINKEN_WORLD_ORIGIN_EAST
#define FINKEN_WORLD_ORIGIN_EAST 1.5   ///< [m] arena x of the flight plan's origin (SwarmLab: its centre)
#endif
#ifndef FINKEN_WORLD_ORIGIN_NORTH
#define FINKEN_WORLD_ORIGIN_NORTH 2.0  ///< [m] arena y of the flight plan's origin
#endif
#ifndef FINKEN_WORLD_WALLS_PERIOD
#define FINKEN_WORLD_WALLS_PERIOD 1.0  ///< [s] between two rows per wall segment in the walls log
#endif

struct finken_world_pose finken_world_pose_from_ned(const double ned_pos_m[3], const double ned_vel_mps[3],
    double psi_rad, double origin_east_m, double origin_north_m)
{
  struct finken_world_pose p = {
    .pos_m = { ned_pos_m[1] + origin_east_m, ned_pos_m[0] + origin_north_m, -ned_pos_m[2] },
    .yaw_rad = M_PI / 2.0 - psi_rad,
    .speed_mps = hypot(ned_vel_mps[0], ned_vel_mps[1]),
  };
  return p;
}

/**
 * A relative XML file name under $PAPARAZZI_HOME; anything else as given: an absolute path, a one-line sensor model
 * (not ending in ".xml", as nps_sensor_model_from_define tells them apart), any name when PAPARAZZI_HOME is unset.
 */
static const char *in_paparazzi_home(const char *file, char *buf, size_t len)
{
  const char *home = getenv("PAPARAZZI_HOME");
  const size_t n = strlen(file);
  if (file[0] == '/' || home == NULL || n < 4 || strcmp(file + n - 4, ".xml") != 0) {
    return file;
  }
  snprintf(buf, len, "%s/%s", home, file);
  return buf;
}

/** A log path in $FINKEN_WORLD_OUT, or NULL when it is unset. */
static const char *log_path(const char *name, char *buf, size_t len)
{
  const char *out = getenv("FINKEN_WORLD_OUT");
  if (out == NULL || out[0] == '\0') {
    return NULL;
  }
  snprintf(buf, len, "%s/%s_%d.csv", out, name, (int)FINKEN_WORLD_AC_ID);
  return buf;
}

/** Simulated seconds to run ($FINKEN_WORLD_DURATION), or +inf; a value that is no positive number stops the start. */
static double run_duration_s(void)
{
  const char *text = getenv("FINKEN_WORLD_DURATION");
  if (text == NULL || text[0] == '\0') {
    return INFINITY;
  }
  char *end;
  const double d = strtod(text, &end);
  if (*end != '\0' || !(d > 0.0) || !isfinite(d)) {
    fprintf(stderr, "finken_world: FINKEN_WORLD_DURATION=\"%s\" is not a positive number of seconds\n", text);
    exit(EXIT_FAILURE);
  }
  return d;
}

static double world_duration_s;

static void quit(const char *what)
{
  fprintf(stderr, "finken_world: %s\n", what);
  exit(EXIT_FAILURE);
}

static void world_at_exit(void)
{
  if (nps_swarm_free() < 0) {
    perror("finken_world: writing the readings or walls log failed");
  }
}

void finken_world_init(void)
{
  char arena[4096], model[4096], readings[4096], walls[4096], err[NPS_SENSOR_MODEL_ERR_LEN];
  const struct nps_swarm_config cfg = {
    .seed = FINKEN_WORLD_SEED, .vehicles = 1, .first_id = FINKEN_WORLD_AC_ID,
    .arena_file = in_paparazzi_home(FINKEN_WORLD_ARENA, arena, sizeof(arena)),
    .sensor_model = in_paparazzi_home(FINKEN_WORLD_SENSOR_MODEL, model, sizeof(model)),
    .readings_path = log_path("readings", readings, sizeof(readings)),
    .walls_path = log_path("walls", walls, sizeof(walls)),
    .walls_period_s = FINKEN_WORLD_WALLS_PERIOD,
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    quit(err);
  }
  world_duration_s = run_duration_s();
  atexit(world_at_exit);
  finken_world_periodic();   /* the pose at start, before the first sensor reading */
}

void finken_world_periodic(void)
{
  const double ned_pos_m[3] = { fdm.ltpprz_pos.x, fdm.ltpprz_pos.y, fdm.ltpprz_pos.z };
  const double ned_vel_mps[3] = { fdm.ltpprz_ecef_vel.x, fdm.ltpprz_ecef_vel.y, fdm.ltpprz_ecef_vel.z };
  const struct finken_world_pose p = finken_world_pose_from_ned(ned_pos_m, ned_vel_mps, fdm.ltpprz_to_body_eulers.psi,
                                     FINKEN_WORLD_ORIGIN_EAST, FINKEN_WORLD_ORIGIN_NORTH);
  nps_swarm_set_pose(0, p.pos_m, p.yaw_rad, p.speed_mps);
  /* the sensor modules' clock (they pass get_sys_time_usec() to the simulator): one time base for all */
  const double now_s = get_sys_time_usec() * 1e-6;
  if (nps_swarm_step(now_s) < 0) {
    quit("the arena step failed (out of memory or a log write)");
  }
  if (now_s >= world_duration_s) {
    printf("finken_world: %.1f s simulated (FINKEN_WORLD_DURATION), stopping\n", now_s);
    exit(EXIT_SUCCESS);   /* world_at_exit closes the logs */
  }
}
