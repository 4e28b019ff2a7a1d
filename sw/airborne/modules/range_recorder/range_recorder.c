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
 * @file modules/range_recorder/range_recorder.c
 * Paparazzi glue of the range recorder: ABI in, rows to the files, messages to the downlink (see range_recorder.h).
 */

#include "modules/range_recorder/range_recorder.h"
#include "modules/range_recorder/range_recorder_telemetry.h"
#include "modules/sonar/sonar_array.h"      /* SONAR_ARRAY_*_ID: the senders of the sonar readings */
#include "mcu_periph/sys_time.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#ifdef PPRZ_HOST_MULTI_VEHICLE   /* our host and its tests: the current vehicle's aircraft id */
#include "pprz_host_vehicle.h"
#define RANGE_RECORDER_AC_ID pprz_vehicle_ac_id()
#else
#include "generated/airframe.h"  /* AC_ID */
#define RANGE_RECORDER_AC_ID AC_ID
#endif

/** Record to files (FALSE: telemetry only) */
#ifndef RANGE_RECORDER_FILE_ENABLED
#define RANGE_RECORDER_FILE_ENABLED TRUE
#endif
/** The readings file; "{ac_id}" stands for the aircraft id, "" for no file. Our multi-copter host: none (it writes
 * readings.csv itself, with the truth), unless $RANGE_RECORDER_OUT_ENV names a folder */
#ifndef RANGE_RECORDER_FILE
#ifdef PPRZ_HOST_MULTI_VEHICLE
#define RANGE_RECORDER_FILE ""
#else
#define RANGE_RECORDER_FILE "/tmp/finken_record_{ac_id}.csv"
#endif
#endif
/** The decisions file, as RANGE_RECORDER_FILE */
#ifndef RANGE_RECORDER_DECISIONS_FILE
#ifdef PPRZ_HOST_MULTI_VEHICLE
#define RANGE_RECORDER_DECISIONS_FILE ""
#else
#define RANGE_RECORDER_DECISIONS_FILE "/tmp/finken_record_decisions_{ac_id}.csv"
#endif
#endif
/** An environment variable naming a folder: when set and not empty, the files are record_<AC_ID>.csv and
 * record_decisions_<AC_ID>.csv there instead (make paparazzi-check and paparazzi-sim set FINKEN_WORLD_OUT to the
 * run's output folder for each NPS process, as finken_world's logs) */
#ifndef RANGE_RECORDER_OUT_ENV
#define RANGE_RECORDER_OUT_ENV "FINKEN_WORLD_OUT"
#endif
/** Seconds between two flushes of the files to the operating system [s] (at most the rows of this long are lost
 * when the process is killed); checked by the periodic task (10 Hz) */
#ifndef RANGE_RECORDER_FLUSH_PERIOD
#define RANGE_RECORDER_FLUSH_PERIOD 1.0f
#endif
/** Send FINKEN_RANGE_READING and FINKEN_WALL_DECISION on each reading and decision (needs a telemetry module) */
#ifndef RANGE_RECORDER_TELEMETRY
#define RANGE_RECORDER_TELEMETRY TRUE
#endif
/** Sender ids bound for the ranging distances and the decisions (ABI_BROADCAST: any) */
#ifndef RANGE_RECORDER_RANGING_SENDER_ID
#define RANGE_RECORDER_RANGING_SENDER_ID ABI_BROADCAST
#endif
#ifndef RANGE_RECORDER_WALL_SENDER_ID
#define RANGE_RECORDER_WALL_SENDER_ID ABI_BROADCAST
#endif

_Static_assert(RANGE_RECORDER_FLUSH_PERIOD >= 0.f && RANGE_RECORDER_FLUSH_PERIOD <= 3600.f,
               "RANGE_RECORDER_FLUSH_PERIOD must be 0 to 3600 [s]");

VEHICLE_LOCAL_DEFINE(struct range_recorder, range_recorder);

/** The horizontal sonar (0 front .. 3 left) of an OBSTACLE_DETECTION sender; -1 for any other sender. */
static int horizontal_sonar(uint8_t sender_id)
{
  static const uint8_t senders[4] = {
    SONAR_ARRAY_FRONT_ID, SONAR_ARRAY_RIGHT_ID, SONAR_ARRAY_BACK_ID, SONAR_ARRAY_LEFT_ID
  };
  for (int i = 0; i < 4; i++) {
    if (sender_id == senders[i]) {
      return i;
    }
  }
  return -1;
}

/** A file that failed: said once on stderr, closed; nothing more is written to it. */
static void file_failed(struct range_recorder_file *file, int err)
{
  fprintf(stderr, "range_recorder: writing %s failed (%s): no more rows to it\n", file->path, strerror(err));
  fclose(file->f);
  file->f = NULL;
}

static void write_row(struct range_recorder_file *file, const char *row, size_t len)
{
  if (file->f == NULL || len == 0) {
    return;
  }
  if (fwrite(row, 1, len, file->f) != len) {
    file_failed(file, errno);
    return;
  }
  file->rows++;
}

static void flush_file(struct range_recorder_file *file)
{
  if (file->f != NULL && fflush(file->f) == EOF) {
    file_failed(file, errno);
  }
}

static int open_file(struct range_recorder_file *file, const char *path, const char *header)
{
  file->f = NULL;
  file->rows = 0;
  file->path[0] = '\0';
  if (path == NULL || path[0] == '\0') {
    return 0;
  }
  if (strlen(path) >= sizeof(file->path)) {
    fprintf(stderr, "range_recorder: the path %s is longer than %d bytes: not recorded\n", path,
            RANGE_RECORDER_PATH_LEN - 1);
    return -1;
  }
  strcpy(file->path, path);
  file->f = fopen(path, "we");   /* e: close on exec (glibc, musl) */
  if (file->f == NULL || fputs(header, file->f) == EOF) {
    fprintf(stderr, "range_recorder: cannot write %s (%s): not recorded\n", path, strerror(errno));
    if (file->f != NULL) {
      fclose(file->f);
      file->f = NULL;
    }
    return -1;
  }
  return 0;
}

static int close_file(struct range_recorder_file *file)
{
  if (file->f == NULL) {
    return 0;
  }
  const bool write_error = ferror(file->f) != 0;
  errno = 0;
  const bool close_error = fclose(file->f) != 0;
  file->f = NULL;
  if (write_error || close_error) {
    fprintf(stderr, "range_recorder: writing %s failed (%s): its last rows may be missing\n", file->path,
            errno != 0 ? strerror(errno) : "stream error");
    return -1;
  }
  return 0;
}

int range_recorder_close(void)
{
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  const int readings = close_file(&rr->readings);
  const int decisions = close_file(&rr->decisions);
  return readings < 0 || decisions < 0 ? -1 : 0;
}

int range_recorder_open(const char *readings_path, const char *decisions_path)
{
  range_recorder_close();
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  const int readings = open_file(&rr->readings, readings_path, RANGE_RECORDER_READINGS_HEADER);
  const int decisions = open_file(&rr->decisions, decisions_path, RANGE_RECORDER_DECISIONS_HEADER);
  rr->flushed_us = get_sys_time_usec();
  return readings < 0 || decisions < 0 ? -1 : 0;
}

static void record_reading(uint32_t stamp_us, uint8_t sensor, uint16_t peer, float measured_m)
{
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  const struct range_recorder_reading r = {
    .t_us = range_recorder_clock_us(&rr->clock, stamp_us), .vehicle = RANGE_RECORDER_AC_ID, .sensor = sensor,
    .peer = peer, .measured_m = measured_m,
  };
  if (rr->readings.f != NULL) {
    char row[RANGE_RECORDER_ROW_LEN];
    write_row(&rr->readings, row, range_recorder_reading_row(row, sizeof(row), &r));
  }
  if (RANGE_RECORDER_TELEMETRY) {
    range_recorder_telemetry_reading(stamp_us, sensor, peer, measured_m);
  }
}

/** A horizontal sonar's reading (OBSTACLE_DETECTION has no stamp: sonar_array publishes it as it reads it). */
static void on_obstacle(uint8_t sender_id, float distance, float elevation, float heading)
{
  (void)elevation, (void)heading;
  const int sonar = horizontal_sonar(sender_id);
  if (sonar >= 0) {
    record_reading(get_sys_time_usec(), (uint8_t)sonar, RANGE_RECORDER_NO_PEER, distance);
  }
}

static void on_agl(uint8_t sender_id, uint32_t stamp, float distance)
{
  (void)sender_id;   /* bound to SONAR_ARRAY_DOWN_ID only */
  record_reading(stamp, RANGE_RECORDER_SONAR_DOWN, RANGE_RECORDER_NO_PEER, distance);
}

static void on_ranging(uint8_t sender_id, uint32_t stamp, uint16_t peer_id, float distance)
{
  (void)sender_id;
  record_reading(stamp, RANGE_RECORDER_RANGING, peer_id, distance);
}

static void on_wall_detection(uint8_t sender_id, uint32_t stamp, uint8_t sonar, float heading, uint8_t target_class,
                              float confidence, float attraction_distance, float repulsion_distance,
                              uint8_t baseline_class)
{
  (void)sender_id, (void)heading, (void)attraction_distance;
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  const struct range_recorder_decision d = {
    .t_us = range_recorder_clock_us(&rr->clock, stamp), .vehicle = RANGE_RECORDER_AC_ID, .sonar = sonar,
    .measured_m = repulsion_distance, .detector_class = target_class, .confidence = confidence,
    .baseline_class = baseline_class,
  };
  if (rr->decisions.f != NULL) {
    char row[RANGE_RECORDER_ROW_LEN];
    write_row(&rr->decisions, row, range_recorder_decision_row(row, sizeof(row), &d));
  }
  if (RANGE_RECORDER_TELEMETRY) {
    range_recorder_telemetry_decision(stamp, sonar, target_class, confidence, repulsion_distance, baseline_class);
  }
}

#ifndef PPRZ_HOST_MULTI_VEHICLE
/* one aircraft per process: its files are closed when the process exits (our host keeps the vehicles' state only
 * until its run ends; stdio flushes what an open file still holds at exit) */
static void close_at_exit(void)
{
  range_recorder_close();
}
#endif

void range_recorder_init(void)
{
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  rr->clock = (struct range_recorder_clock) { 0 };
  AbiBindMsgOBSTACLE_DETECTION(ABI_BROADCAST, &rr->obstacle_ev, on_obstacle);
  AbiBindMsgAGL(SONAR_ARRAY_DOWN_ID, &rr->agl_ev, on_agl);
  AbiBindMsgRANGING_DISTANCE(RANGE_RECORDER_RANGING_SENDER_ID, &rr->ranging_ev, on_ranging);
  AbiBindMsgWALL_DETECTION(RANGE_RECORDER_WALL_SENDER_ID, &rr->wall_ev, on_wall_detection);
  if (!RANGE_RECORDER_FILE_ENABLED) {
    return;
  }
  const char *dir = getenv(RANGE_RECORDER_OUT_ENV);
  const unsigned ac_id = RANGE_RECORDER_AC_ID;
  char readings[RANGE_RECORDER_PATH_LEN], decisions[RANGE_RECORDER_PATH_LEN];
  if (range_recorder_file_path(readings, sizeof(readings), dir, "record", RANGE_RECORDER_FILE, ac_id) < 0 ||
      range_recorder_file_path(decisions, sizeof(decisions), dir, "record_decisions", RANGE_RECORDER_DECISIONS_FILE,
                               ac_id) < 0) {
    fprintf(stderr, "range_recorder: a file's path is longer than %d bytes: nothing recorded to files\n",
            RANGE_RECORDER_PATH_LEN - 1);
    return;
  }
  range_recorder_open(readings, decisions);
#ifndef PPRZ_HOST_MULTI_VEHICLE
  static bool closed_at_exit = false;
  if (!closed_at_exit) {
    closed_at_exit = atexit(close_at_exit) == 0;
  }
#endif
}

void range_recorder_periodic(void)
{
  struct range_recorder *rr = VEHICLE_LOCAL(range_recorder);
  if (rr->readings.f == NULL && rr->decisions.f == NULL) {
    return;
  }
  const uint32_t now_us = get_sys_time_usec();
  if (now_us - rr->flushed_us < (uint32_t)(RANGE_RECORDER_FLUSH_PERIOD * 1e6f)) {
    return;
  }
  rr->flushed_us = now_us;
  flush_file(&rr->readings);
  flush_file(&rr->decisions);
}
