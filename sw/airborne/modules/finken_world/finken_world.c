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
 * relative paths (the overlay puts ours under conf/); the environment variable FINKEN_WORLD_SENSOR_MODEL names another
 * sensor model for one run (a calibrated model.xml) without a rebuild.
 * The arena is shared with the NPS processes of the other aircraft (nps_swarm_shared.h): the world named by the
 * environment variable FINKEN_WORLD (else FINKEN_WORLD_NAME), of the run FINKEN_WORLD_RUN (else none).
 * Logs: when the environment variable FINKEN_WORLD_OUT names a directory, readings_<AC_ID>.csv (range-log format),
 * poses_<AC_ID>.csv, detections_<AC_ID>.csv and walls_<AC_ID>.csv (rows only while this aircraft owns the walls)
 * are written there, every time in world time. Pose rows (position, yaw and the full attitude quaternion of NPS's
 * flight model, nps_run_log.h) come every FINKEN_WORLD_POSES_PERIOD, or at the environment's
 * FINKEN_WORLD_POSE_RATE rows per second. When FINKEN_WORLD_DURATION holds a number of seconds, the process
 * ends (exit status 0, logs closed) once the simulated time reaches it: NPS itself runs until it is stopped. SIGINT
 * and SIGTERM end it the same way at the next step.
 */

#include "modules/finken_world/finken_world.h"

#include "mcu_periph/sys_time.h"
#include "modules/core/abi.h"
#include "modules/wall_detector/wall_detector_reading.h"   /* wall_detector_class_name */
#include "nps_arena_start.h"
#include "nps_csv.h"
#include "nps_fdm.h"
#include "nps_fdm_finken.h"
#include "nps_raycast.h"        /* nps_sonar_name */
#include "nps_run_log.h"
#include "nps_sensor_model.h"   /* NPS_SENSOR_MODEL_ERR_LEN */
#include "nps_swarm.h"
#include "nps_swarm_shared.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef PPRZ_HOST_MULTI_VEHICLE   /* our host's tests: the stand-ins' aircraft id, real time */
#include "pprz_host_vehicle.h"
#define FINKEN_WORLD_BUILD_AC_ID pprz_vehicle_ac_id()
#define FINKEN_WORLD_TIME_FACTOR 1.0
#else
#include "generated/airframe.h"  /* AC_ID and the airframe's FINKEN_WORLD section */
#include "nps_main.h"
#define FINKEN_WORLD_BUILD_AC_ID AC_ID
#define FINKEN_WORLD_TIME_FACTOR nps_main.host_time_factor   /* NPS's --time_factor */
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
#ifndef FINKEN_WORLD_AIRCRAFT
#define FINKEN_WORLD_AIRCRAFT 1        ///< aircraft of the swarm, for the start places (env FINKEN_WORLD_AIRCRAFT overrides)
#endif
#ifndef FINKEN_WORLD_WALLS_PERIOD
#define FINKEN_WORLD_WALLS_PERIOD 1.0  ///< [s] between two rows per wall segment in the walls log
#endif
#ifndef FINKEN_WORLD_POSES_PERIOD
#define FINKEN_WORLD_POSES_PERIOD 0.1  ///< [s] between two rows of the poses log (env FINKEN_WORLD_POSE_RATE [Hz] overrides)
#endif
#ifndef FINKEN_WORLD_NAME
#define FINKEN_WORLD_NAME "finken"     ///< world shared by the NPS processes of a swarm (env FINKEN_WORLD overrides)
#endif
#ifndef FINKEN_WORLD_PEER_TIMEOUT
#define FINKEN_WORLD_PEER_TIMEOUT 2.0  ///< [s] wall clock without news after which another aircraft has left
#endif
#ifndef FINKEN_WORLD_SYNC_WINDOW
#define FINKEN_WORLD_SYNC_WINDOW 0.0   ///< [s] how far behind another aircraft may be before this one waits for it
#endif

static unsigned own_id;   ///< this aircraft's id in the world (world_ac_id), set first at the start

struct finken_world_pose finken_world_pose_from_ned(const double ned_pos_m[3], const double ned_vel_mps[3],
    double psi_rad)
{
  struct finken_world_pose p = {
    .pos_m = { ned_pos_m[1], ned_pos_m[0], -ned_pos_m[2] },
    .yaw_rad = M_PI / 2.0 - psi_rad,
    .speed_mps = hypot(ned_vel_mps[0], ned_vel_mps[1]),
  };
  return p;
}

void finken_world_attitude_from_ned(const double ned_quat[4], double q_xyzw[4])
{
  /* ned_quat = (qi, qx, qy, qz), qi the scalar: Paparazzi's ltp_to_body quaternion, whose rotation (Hamilton)
   * turns the body frame FRD (x forward, y right, z down) into the local NED frame: double_eulers_of_quat gives
   * psi = atan2(2 (qx qy + qi qz), 1 - 2 (qy^2 + qz^2)), a turn by psi about down. The rotation we log, from body
   * FLU into the arena's ENU, is (ENU <- NED) (NED <- FRD) (FRD <- FLU), where ENU <- NED swaps x and y and negates
   * z, a half turn about (1, 1, 0) / sqrt(2), quaternion (w; x, y, z) = (0; 1, 1, 0) / sqrt(2), and FRD <- FLU
   * negates y and z, a half turn about x, (0; 1, 0, 0). Multiplied out (and negated: q and -q are the same rotation):
   *   (w; x, y, z)_ENU<-FLU = (qi + qz; qx + qy, qx - qy, qi - qz) / sqrt(2)
   * (a heading psi alone gives the turn by pi/2 - psi about up). */
  const double h = M_SQRT1_2;
  q_xyzw[0] = h * (ned_quat[1] + ned_quat[2]);
  q_xyzw[1] = h * (ned_quat[1] - ned_quat[2]);
  q_xyzw[2] = h * (ned_quat[0] - ned_quat[3]);
  q_xyzw[3] = h * (ned_quat[0] + ned_quat[3]);
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
  snprintf(buf, len, "%s/%s_%d.csv", out, name, (int)own_id);
  return buf;
}

/** An environment variable, or `otherwise` when it is unset or empty. */
static const char *env_or(const char *name, const char *otherwise)
{
  const char *value = getenv(name);
  return value != NULL && value[0] != '\0' ? value : otherwise;
}

/**
 * The environment variable `name` as a whole number in 1..NPS_WORLD_MAX_AIRCRAFT, or `otherwise` when it is unset or
 * empty; anything else stops the start, saying it is no `what` in that range.
 */
static unsigned env_aircraft_number(const char *name, unsigned otherwise, const char *what)
{
  const char *text = getenv(name);
  if (text == NULL || text[0] == '\0') {
    return otherwise;
  }
  char *end;
  const long n = strtol(text, &end, 10);
  if (*end != '\0' || n < 1 || n > NPS_WORLD_MAX_AIRCRAFT) {
    fprintf(stderr, "finken_world: %s=\"%s\" is not %s in 1..%d\n", name, text, what, NPS_WORLD_MAX_AIRCRAFT);
    exit(EXIT_FAILURE);
  }
  return (unsigned)n;
}

/** Aircraft of the swarm: $FINKEN_WORLD_AIRCRAFT, else FINKEN_WORLD_AIRCRAFT. */
static unsigned swarm_size(void)
{
  return env_aircraft_number("FINKEN_WORLD_AIRCRAFT", FINKEN_WORLD_AIRCRAFT, "a number of aircraft");
}

/**
 * This aircraft's id in the world: $FINKEN_WORLD_AC_ID (one build flown as several aircraft, as make bench does; the
 * telemetry keeps the build's AC_ID), else the build's AC_ID.
 */
static unsigned world_ac_id(void)
{
  return env_aircraft_number("FINKEN_WORLD_AC_ID", FINKEN_WORLD_BUILD_AC_ID, "an aircraft id");
}

static void quit(const char *what)
{
  fprintf(stderr, "finken_world: %s\n", what);
  exit(EXIT_FAILURE);
}

/**
 * Move this aircraft's flight model to where copter AC_ID - 1 of the swarm starts in our host: arena (x, y) is
 * (east, north) of the flight plan's origin, arena yaw pi/2 - heading (finken_world.h).
 */
static void place_at_start(void)
{
  const unsigned n = swarm_size(), v = (own_id - 1u) % n;
  double start_m[NPS_WORLD_MAX_AIRCRAFT][2], yaw_rad[NPS_WORLD_MAX_AIRCRAFT];
  char err[256];
  if (nps_arena_start_poses(nps_swarm_arena(), n, start_m, yaw_rad, err, sizeof(err)) < 0) {
    quit(err);
  }
  nps_fdm_finken_place(start_m[v][1], start_m[v][0], M_PI / 2.0 - yaw_rad[v]);
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

/**
 * Seconds between two pose rows: 1 / $FINKEN_WORLD_POSE_RATE (rows per second), else FINKEN_WORLD_POSES_PERIOD. A
 * rate that is no positive number, or one above the rate the module runs at (PERIODIC_FREQUENCY: a row is the pose
 * of a step, at most one per step), stops the start.
 */
static double poses_period_s(void)
{
  const char *text = getenv("FINKEN_WORLD_POSE_RATE");
  double period_s = FINKEN_WORLD_POSES_PERIOD;
  if (text != NULL && text[0] != '\0') {
    char *end;
    const double hz = strtod(text, &end);
    if (*end != '\0' || !(hz > 0.0) || !isfinite(hz)) {
      fprintf(stderr, "finken_world: FINKEN_WORLD_POSE_RATE=\"%s\" is not a positive number of pose rows per second\n",
              text);
      exit(EXIT_FAILURE);
    }
    period_s = 1.0 / hz;
  }
#ifdef PERIODIC_FREQUENCY
  if (!(period_s * PERIODIC_FREQUENCY >= 1.0 - 1e-9)) {
    fprintf(stderr, "finken_world: pose rows at %g Hz: above the %g Hz the module runs at (PERIODIC_FREQUENCY); a row "
            "is the pose of one step, so at most %g Hz\n", 1.0 / period_s, (double)PERIODIC_FREQUENCY,
            (double)PERIODIC_FREQUENCY);
    exit(EXIT_FAILURE);
  }
#endif
  return period_s;
}

/**
 * NPS's attitude of this aircraft, local NED -> body FRD (qi, qx, qy, qz): fdm.ltpprz_to_body_quat (the frame of
 * fdm.ltpprz_pos; fdm_finken fills it), or, where it is unset (no unit quaternion: the host's scripted flight models
 * in tests), the quaternion of fdm.ltpprz_to_body_eulers (Paparazzi's double_quat_of_eulers, ZYX).
 */
static void fdm_attitude(double q[4])
{
  const struct DoubleQuat *f = &fdm.ltpprz_to_body_quat;
  const double norm = sqrt(f->qi * f->qi + f->qx * f->qx + f->qy * f->qy + f->qz * f->qz);
  if (fabs(norm - 1.0) < 1e-3) {
    q[0] = f->qi / norm, q[1] = f->qx / norm, q[2] = f->qy / norm, q[3] = f->qz / norm;
    return;
  }
  const struct DoubleEulers *e = &fdm.ltpprz_to_body_eulers;
  const double cf = cos(0.5 * e->phi), sf = sin(0.5 * e->phi), ct = cos(0.5 * e->theta), st = sin(0.5 * e->theta);
  const double cp = cos(0.5 * e->psi), sp = sin(0.5 * e->psi);
  q[0] = cf * ct * cp + sf * st * sp;
  q[1] = sf * ct * cp - cf * st * sp;
  q[2] = cf * st * cp + sf * ct * sp;
  q[3] = cf * ct * sp - sf * st * cp;
}

static struct {
  double duration_s;
  double poses_period_s;
  FILE *poses, *detections;
  char poses_path[4096], detections_path[4096];
  double next_pose_s;
  abi_event detection_ev;
} world;

static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int signum)
{
  stop_signal = signum;
}

/** Open a log of ours with its header; quits naming the file when it cannot be written. */
static FILE *open_log(const char *path, const char *header)
{
  FILE *f = path != NULL ? fopen(path, "w") : NULL;
  if (path != NULL && (f == NULL || fputs(header, f) == EOF)) {
    fprintf(stderr, "finken_world: cannot write %s\n", path);
    exit(EXIT_FAILURE);
  }
  return f;
}

static bool close_log(FILE *f, const char *path)
{
  if (f != NULL && (ferror(f) | fclose(f)) != 0) {
    fprintf(stderr, "finken_world: writing %s failed\n", path);
    return false;
  }
  return true;
}

/** What the exchange with the other aircraft achieved (docs/paparazzi.md, "A swarm in Paparazzi's NPS"). */
static void print_exchange_figures(void)
{
  const struct nps_swarm_shared_stats *st = nps_swarm_shared_stats();
  printf("finken_world: aircraft %d: %lu steps, %lu peer poses (%lu moved on from an older sample, age mean %.2g s, "
         "max %.2g s), exchange %.3g us per step (of which waiting for others %.3g us)\n", (int)own_id,
         st->steps, st->peer_poses, st->extrapolated, st->peer_poses > 0 ? st->age_sum_s / st->peer_poses : 0.0,
         st->age_max_s, st->steps > 0 ? st->exchange_s / st->steps * 1e6 : 0.0,
         st->steps > 0 ? st->wait_s / st->steps * 1e6 : 0.0);
  fflush(stdout);
}

static void world_at_exit(void)
{
  print_exchange_figures();
  nps_swarm_unshare();
  bool written = close_log(world.poses, world.poses_path) & close_log(world.detections, world.detections_path);
  if (nps_swarm_free() < 0) {
    perror("finken_world: writing the readings or walls log failed");
    written = false;
  }
  if (!written) {
    _exit(EXIT_FAILURE);
  }
}

/** A WALL_DETECTION of this aircraft's wall detector, with the ground truth of the reading it judged. */
static void on_detection(uint8_t sender_id, uint32_t stamp, uint8_t sonar, float heading, uint8_t target_class,
                         float confidence, float attraction_distance, float repulsion_distance, uint8_t baseline_class)
{
  (void)sender_id, (void)heading, (void)attraction_distance;
  double true_range_m;
  bool target_copter;
  nps_swarm_sonar_last_truth(0, sonar, &true_range_m, &target_copter);
  const struct nps_detection d = {
    .t_s = nps_swarm_usec_to_s(stamp) + nps_swarm_shared_offset_s(), .ac_id = own_id,
    .sonar = nps_sonar_name((enum nps_sonar)sonar), .true_range_m = true_range_m, .measured_m = repulsion_distance,
    .target_copter = target_copter, .detector_class = wall_detector_class_name(target_class),
    .confidence = confidence, .baseline_class = wall_detector_class_name(baseline_class),
  };
  char row[NPS_DETECTION_LOG_ROW_LEN];
  fwrite(row, 1, nps_detection_log_row(row, &d), world.detections);
}

void finken_world_init(void)
{
  own_id = world_ac_id();
  char arena[4096], model[4096], readings[4096], walls[4096], err[NPS_SENSOR_MODEL_ERR_LEN];
  /* this aircraft is copter 0; every other id of the world follows it (nps_swarm_shared.h) */
  const struct nps_swarm_config cfg = {
    .seed = FINKEN_WORLD_SEED, .vehicles = NPS_WORLD_MAX_AIRCRAFT, .first_id = own_id,
    .max_id = NPS_WORLD_MAX_AIRCRAFT,
    .arena_file = in_paparazzi_home(FINKEN_WORLD_ARENA, arena, sizeof(arena)),
    .sensor_model = in_paparazzi_home(env_or("FINKEN_WORLD_SENSOR_MODEL", FINKEN_WORLD_SENSOR_MODEL), model,
                                      sizeof(model)),
    .readings_path = log_path("readings", readings, sizeof(readings)),
    .walls_path = log_path("walls", walls, sizeof(walls)),
    .walls_period_s = FINKEN_WORLD_WALLS_PERIOD,
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    quit(err);
  }
  const struct nps_swarm_shared_config shared = {
    .name = env_or("FINKEN_WORLD", FINKEN_WORLD_NAME), .run = env_or("FINKEN_WORLD_RUN", ""),
    .ac_id = own_id, .time_factor = FINKEN_WORLD_TIME_FACTOR,
    .peer_timeout_s = FINKEN_WORLD_PEER_TIMEOUT, .sync_window_s = FINKEN_WORLD_SYNC_WINDOW,
  };
  if (nps_swarm_share(&shared, nps_swarm_usec_to_s(get_sys_time_usec()), err, sizeof(err)) < 0) {
    quit(err);
  }
  place_at_start();
  world.duration_s = run_duration_s();
  world.poses_period_s = poses_period_s();
  world.poses = open_log(log_path("poses", world.poses_path, sizeof(world.poses_path)), NPS_POSE_LOG_HEADER);
  world.detections = open_log(log_path("detections", world.detections_path, sizeof(world.detections_path)),
                              NPS_DETECTION_LOG_HEADER);
  if (world.detections != NULL) {
    AbiBindMsgWALL_DETECTION(ABI_BROADCAST, &world.detection_ev, on_detection);
  }
  atexit(world_at_exit);
  signal(SIGINT, on_stop_signal);
  signal(SIGTERM, on_stop_signal);
  printf("finken_world: aircraft %d in world \"%s\" (world time = simulated time + %.3f s)\n",
         (int)own_id, shared.name, nps_swarm_shared_offset_s());
  finken_world_periodic();   /* the pose at start, before the first sensor reading */
}

/** Who joined or left the world, a line each. */
static void print_news(void)
{
  const char *news = nps_swarm_shared_news();
  for (const char *line = news; line != NULL && *line != '\0';) {
    const size_t len = strcspn(line, "\n");
    printf("finken_world: %.*s\n", (int)len, line);
    line += len + (line[len] == '\n');
  }
  if (news != NULL) {
    fflush(stdout);
  }
}

/** Stop at a step boundary: a signal, or the run's duration reached; world_at_exit closes the logs. */
static void stop_when_due(double now_s)
{
  if (stop_signal != 0) {
    printf("finken_world: %s at %.1f s, stopping\n", stop_signal == SIGINT ? "SIGINT" : "SIGTERM", now_s);
    exit(EXIT_SUCCESS);
  }
  if (now_s >= world.duration_s) {
    printf("finken_world: %.1f s simulated (FINKEN_WORLD_DURATION), stopping\n", now_s);
    exit(EXIT_SUCCESS);
  }
}

void finken_world_periodic(void)
{
  const double ned_pos_m[3] = { fdm.ltpprz_pos.x, fdm.ltpprz_pos.y, fdm.ltpprz_pos.z };
  const double ned_vel_mps[3] = { fdm.ltpprz_ecef_vel.x, fdm.ltpprz_ecef_vel.y, fdm.ltpprz_ecef_vel.z };
  const struct finken_world_pose p = finken_world_pose_from_ned(ned_pos_m, ned_vel_mps, fdm.ltpprz_to_body_eulers.psi);
  nps_swarm_set_pose(0, p.pos_m, p.yaw_rad, p.speed_mps);
  /* the sensor modules' clock (they pass get_sys_time_usec() to the simulator): one time base for all */
  const double now_s = nps_swarm_usec_to_s(get_sys_time_usec());
  const int met = nps_swarm_shared_step(now_s);
  if (met < 0) {
    quit("the arena step failed (out of memory or a log write)");
  }
  double pos_m[3] = { p.pos_m[0], p.pos_m[1], p.pos_m[2] };
  if (met && nps_swarm_pushed(0)) {   /* a wall or another copter stopped it: the flight model takes the correction */
    nps_swarm_get_position(0, pos_m);
    nps_fdm_finken_take_contact(pos_m[1], pos_m[0]);
  }
  print_news();
  /* pose rows at whole multiples of the period of world time, the same for every aircraft (the swarm's cohesion is
   * taken over the aircraft's rows of one time): the pose of the step that reaches one, at most a step after it */
  const double world_s = now_s + nps_swarm_shared_offset_s();
  if (world.poses != NULL && world_s >= world.next_pose_s) {
    const double row_s = world.poses_period_s * floor(world_s / world.poses_period_s);
    double ned_quat[4], q[4];
    fdm_attitude(ned_quat);
    finken_world_attitude_from_ned(ned_quat, q);
    /* where the sensors see this copter: the flight model's position, after the world's contacts (it took them) */
    char row[NPS_POSE_LOG_ROW_LEN];
    fwrite(row, 1, nps_pose_log_row(row, row_s, own_id, pos_m, p.yaw_rad, q), world.poses);
    world.next_pose_s = row_s + world.poses_period_s;
  }
  stop_when_due(now_s);
}
