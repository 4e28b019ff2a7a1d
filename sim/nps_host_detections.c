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
 * @file nps_host_detections.c
 * The host's log of the wall detector's decisions (see nps_host_detections.h).
 */

#include "nps_host_detections.h"

#include "modules/core/abi.h"
#include "modules/wall_detector/wall_detector_reading.h"
#include "nps_csv.h"
#include "nps_run_log.h"
#include "nps_raycast.h"
#include "nps_swarm.h"
#include "pprz_host_vehicle.h"

#include <errno.h>
#include <stdbool.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static FILE *detections;          ///< written once (under open_lock), read by every thread of the modules phase
static char detections_path[4096];
static char *detections_buffer;   ///< its stdio buffer (nps_csv_fopen)
static abi_event *detection_ev;   ///< one binding per copter
static pthread_mutex_t open_lock = PTHREAD_MUTEX_INITIALIZER;   ///< the first detection may come from any thread
static bool open_failed;          ///< the file could not be created (said once)

/**
 * The file, created with its header on the first detection of the run (by whichever thread has it; the
 * acquire load pairs with the release store, so every thread sees the header written); NULL if it cannot be.
 */
static FILE *detections_file(void)
{
  FILE *f = __atomic_load_n(&detections, __ATOMIC_ACQUIRE);
  if (f != NULL) {
    return f;
  }
  pthread_mutex_lock(&open_lock);
  f = detections;
  if (f == NULL && !open_failed) {   /* said once; the host stops at the write error (nps_host_detections_write_error) */
    f = nps_csv_fopen(detections_path, &detections_buffer);
    if (f == NULL) {
      fprintf(stderr, "error: cannot write %s: %s\n", detections_path, strerror(errno));
      __atomic_store_n(&open_failed, true, __ATOMIC_RELEASE);
    } else {
      fputs(NPS_DETECTION_LOG_HEADER, f);
      __atomic_store_n(&detections, f, __ATOMIC_RELEASE);
    }
  }
  pthread_mutex_unlock(&open_lock);
  return f;
}

static void on_detection(uint8_t sender_id, uint32_t stamp, uint8_t sonar, float heading, uint8_t target_class,
                         float confidence, float attraction_distance, float repulsion_distance, uint8_t baseline_class)
{
  (void)sender_id, (void)heading, (void)attraction_distance;
  FILE *f = detections_file();
  if (f == NULL) {
    return;
  }
  double true_range_m;
  bool target_copter;
  nps_swarm_sonar_last_truth(pprz_vehicle_index, sonar, &true_range_m, &target_copter);
  const struct nps_detection d = {
    .t_s = nps_swarm_usec_to_s(stamp), .ac_id = pprz_vehicle_ac_id(), .sonar = nps_sonar_name((enum nps_sonar)sonar),
    .true_range_m = true_range_m, .measured_m = repulsion_distance, .target_copter = target_copter,
    .detector_class = wall_detector_class_name(target_class), .confidence = confidence,
    .baseline_class = wall_detector_class_name(baseline_class),
  };
  char row[NPS_DETECTION_LOG_ROW_LEN];
  const size_t len = nps_detection_log_row(row, &d);
  nps_csv_write(f, row, len);   /* a worker thread's spool: appended in copter order */
}

void nps_host_detections_start(const char *path)
{
  snprintf(detections_path, sizeof(detections_path), "%s", path);
  open_failed = false;
  detection_ev = calloc(pprz_vehicle_count, sizeof(*detection_ev));
  for (unsigned v = 0; detection_ev != NULL && v < pprz_vehicle_count; v++) {
    pprz_vehicle_select(v);
    AbiBindMsgWALL_DETECTION(ABI_BROADCAST, &detection_ev[v], on_detection);
  }
}

const char *nps_host_detections_write_error(void)
{
  FILE *f = __atomic_load_n(&detections, __ATOMIC_ACQUIRE);
  return __atomic_load_n(&open_failed, __ATOMIC_ACQUIRE) || (f != NULL && ferror(f)) ? detections_path : NULL;
}

int nps_host_detections_stop(void)
{
  int rc = 0;
  if (detections != NULL && (ferror(detections) | fclose(detections)) != 0) {
    rc = -1;
  }
  detections = NULL;
  free(detections_buffer);
  detections_buffer = NULL;
  free(detection_ev);
  detection_ev = NULL;
  return rc;
}
