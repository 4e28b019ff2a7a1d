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
 * @file nps_host_ranging_replay.c
 * Replay of a candump log of the ranging units into the host's copters (see nps_host_ranging_replay.h).
 */

#include "nps_host_ranging_replay.h"

#include "modules/ranging/ranging_can_candump.h"
#include "modules/ranging/ranging_can_rx.h"
#include "nps_csv.h"
#include "nps_swarm.h"
#include "pprz_host_vehicle.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** The module the distances go to; weak so a host without virtual_ranging still links (and says so). */
extern void virtual_ranging_report(uint16_t peer_id, float distance_m, uint32_t stamp_us) __attribute__((weak));

/** A copter's distance older than this is stale for the bus logic [us] (VIRTUAL_RANGING_STALE_TIME). */
#define NPS_REPLAY_STALE_US 500000u

static struct {
  FILE *log, *out;
  const char *path;
  const char *out_path;       ///< ranging_replay.csv (staged: nps_host_outputs.h)
  unsigned line, vehicles, readings, other_bus;
  char ifname[RANGING_CAN_CANDUMP_IFNAME_LEN];  ///< the replayed bus
  struct ranging_can_rx *rx;          ///< one decoder per copter
  struct ranging_can_candump_line next;
  bool pending;                       ///< next holds a frame not delivered yet
  uint64_t first_us;
} replay;

/** Longest candump line taken [characters]: a real one is under 100; more is no candump log. */
#define NPS_REPLAY_LINE_MAX 511

/** A line of the log that cannot be replayed: said with file:line, the replay stops. */
static int bad_line(const char *why)
{
  fprintf(stderr, "error: %s:%u: %s\n", replay.path, replay.line, why);
  return -1;
}

/**
 * Read the next frame of the log into replay.next; 0 at the end, -1 on a malformed line (too long, a NUL byte, a
 * time before the previous frame's), or when the log cannot be read (e.g. a directory).
 */
static int read_next(void)
{
  char *text = NULL;
  size_t size = 0;
  ssize_t len;
  int rc = 0;
  const uint64_t previous_us = replay.pending ? replay.next.time_us : replay.first_us;
  replay.pending = false;
  while (rc == 0 && (len = getline(&text, &size, replay.log)) >= 0) {
    replay.line++;
    const char *why = NULL;
    int got = 0;
    if (len > NPS_REPLAY_LINE_MAX + 1 || (len == NPS_REPLAY_LINE_MAX + 1 && text[len - 1] != '\n')) {
      rc = bad_line("line longer than 511 characters: not a candump line");
    } else if (memchr(text, '\0', (size_t)len) != NULL) {
      rc = bad_line("a NUL byte in the line: not a candump line");
    } else if ((got = ranging_can_candump_parse(text, &replay.next, &why)) < 0) {
      rc = bad_line(why);
    } else if (got == 1 && replay.next.time_us < previous_us) {
      rc = bad_line("time stamp before the previous frame's: a candump log runs forward in time");
    } else if (got == 1 && replay.ifname[0] == '\0') {
      memcpy(replay.ifname, replay.next.ifname, sizeof(replay.ifname));
    }
    if (rc == 0 && got == 1 && strcmp(replay.next.ifname, replay.ifname) != 0) {
      replay.other_bus++;
    } else if (rc == 0 && got == 1) {
      replay.pending = true;
      rc = 1;
    }
  }
  free(text);
  if (rc == 0 && ferror(replay.log)) {
    fprintf(stderr, "error: cannot read %s: %s\n", replay.path, strerror(errno));
    rc = -1;
  }
  return rc;
}

int nps_host_ranging_replay_open(const char *log_path, const char *out_file, unsigned vehicles)
{
  if (virtual_ranging_report == NULL) {
    fprintf(stderr, "error: --ranging-replay needs the virtual_ranging module in the airframe\n");
    return -1;
  }
  memset(&replay, 0, sizeof(replay));
  replay.path = log_path;
  replay.vehicles = vehicles;
  replay.log = fopen(log_path, "r");
  if (replay.log == NULL) {
    fprintf(stderr, "error: cannot read %s: %s\n", log_path, strerror(errno));
    return -1;
  }
  const char *out_path = out_file;
  replay.out_path = out_file;
  replay.out = fopen(out_path, "w");
  replay.rx = calloc(vehicles, sizeof(*replay.rx));
  if (replay.out == NULL || replay.rx == NULL) {
    fprintf(stderr, "error: cannot write %s: %s\n", out_path, strerror(errno));
    nps_host_ranging_replay_close();
    return -1;
  }
  fputs("t,vehicle,peer,distance\n", replay.out);
  for (unsigned v = 0; v < vehicles; v++) {
    const struct ranging_can_rx_config cfg = {
      .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = (uint8_t)(v + 1), .stale_us = NPS_REPLAY_STALE_US,
    };
    ranging_can_rx_init(&replay.rx[v], &cfg);
  }
  nps_swarm_ranging_disable();
  if (read_next() < 0) {
    nps_host_ranging_replay_close();
    return -1;
  }
  replay.first_us = replay.next.time_us;
  return 0;
}

int nps_host_ranging_replay_step(double t_s)
{
  while (replay.pending && replay.next.time_us - replay.first_us <= (uint64_t)(t_s * 1e6)) {
    const uint32_t stamp_us = (uint32_t)(replay.next.time_us - replay.first_us);
    for (unsigned v = 0; v < replay.vehicles && v < RANGING_CAN_NB_NODES_MAX; v++) {
      struct ranging_can_reading reading;
      if (ranging_can_rx_frame(&replay.rx[v], &replay.next.frame, stamp_us, &reading) == RANGING_CAN_RX_READING) {
        pprz_vehicle_select(v);
        virtual_ranging_report(reading.other_id, reading.range_m, stamp_us);
        char t[NPS_CSV_NUMBER_LEN], d[NPS_CSV_NUMBER_LEN];
        nps_csv_fixed4(t, nps_swarm_usec_to_s(stamp_us));
        nps_csv_fixed4(d, reading.range_m);
        fprintf(replay.out, "%s,%u,%u,%s\n", t, v + 1, reading.other_id, d);
        replay.readings++;
      }
    }
    if (read_next() < 0) {
      return -1;
    }
  }
  return 0;
}

const char *nps_host_ranging_replay_write_error(void)
{
  return replay.out != NULL && ferror(replay.out) ? replay.out_path : NULL;
}

int nps_host_ranging_replay_close(void)
{
  int rc = 0;
  if (replay.log != NULL) {
    fprintf(stderr, "ranging replay: %u distances from %u lines of %s (bus %s; %u frames of other buses skipped)\n",
            replay.readings, replay.line, replay.path, replay.ifname, replay.other_bus);
    fclose(replay.log);
  }
  if (replay.out != NULL && (ferror(replay.out) | fclose(replay.out)) != 0) {
    fprintf(stderr, "error: writing %s failed: %s\n", replay.out_path, strerror(errno));
    rc = -1;
  }
  free(replay.rx);
  memset(&replay, 0, sizeof(replay));
  return rc;
}
