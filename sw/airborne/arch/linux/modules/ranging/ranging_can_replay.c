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
 * @file arch/linux/modules/ranging/ranging_can_replay.c
 * candump log -> frames on a descriptor (see ranging_can_replay.h).
 */

#include "modules/ranging/ranging_can_replay.h"
#include "modules/ranging/ranging_can_candump.h"
#include "modules/ranging/ranging_socketcan.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Longest log line [chars]: "(seconds.usecs) ifname id##f" + 128 hex digits, with room to spare */
#define RANGING_CAN_REPLAY_LINE_LEN 512

struct ranging_can_replay {
  FILE *log;
  char path[256];
  char ifname[RANGING_CAN_CANDUMP_IFNAME_LEN];  ///< "" for all
  int fd_out;
  unsigned line_no;
  bool pending;                                 ///< `next` was parsed but not written yet
  struct ranging_can_candump_line next;
  uint32_t count;
};

struct ranging_can_replay *ranging_can_replay_open(const char *path, const char *ifname, int fd_out,
    char *err, size_t errlen)
{
  if (ifname != NULL && strlen(ifname) >= RANGING_CAN_CANDUMP_IFNAME_LEN) {
    snprintf(err, errlen, "candump replay: interface name '%s' longer than 15 characters", ifname);
    errno = EINVAL;
    return NULL;
  }
  struct ranging_can_replay *r = calloc(1, sizeof(*r));
  if (r == NULL) {
    snprintf(err, errlen, "candump replay: out of memory");
    return NULL;
  }
  r->log = fopen(path, "re");
  if (r->log == NULL) {
    const int saved = errno;
    snprintf(err, errlen, "%s: cannot open: %s", path, strerror(saved));
    free(r);
    errno = saved;
    return NULL;
  }
  snprintf(r->path, sizeof(r->path), "%s", path);
  if (ifname != NULL) {
    strcpy(r->ifname, ifname);
  }
  r->fd_out = fd_out;
  return r;
}

/** Parse the next frame of the log into r->next; 1 a frame, 0 end of log, -1 error (err set). */
static int next_frame(struct ranging_can_replay *r, char *err, size_t errlen)
{
  char line[RANGING_CAN_REPLAY_LINE_LEN];
  while (fgets(line, sizeof(line), r->log) != NULL) {
    r->line_no++;
    if (strchr(line, '\n') == NULL && !feof(r->log)) {
      snprintf(err, errlen, "%s:%u: line longer than %d characters", r->path, r->line_no,
               RANGING_CAN_REPLAY_LINE_LEN - 2);
      errno = EINVAL;
      return -1;
    }
    const char *why;
    const int rc = ranging_can_candump_parse(line, &r->next, &why);
    if (rc < 0) {
      snprintf(err, errlen, "%s:%u: %s", r->path, r->line_no, why);
      errno = EINVAL;
      return -1;
    }
    if (rc > 0 && (r->ifname[0] == '\0' || strcmp(r->ifname, r->next.ifname) == 0)) {
      return 1;
    }
  }
  if (ferror(r->log)) {
    snprintf(err, errlen, "%s:%u: read failed: %s", r->path, r->line_no, strerror(errno));
    return -1;
  }
  return 0;
}

int ranging_can_replay_until(struct ranging_can_replay *r, uint64_t until_us, char *err, size_t errlen)
{
  for (;;) {
    if (!r->pending) {
      const int rc = next_frame(r, err, errlen);
      if (rc <= 0) {
        return rc;
      }
      r->pending = true;
    }
    if (r->next.time_us > until_us) {
      return 1;
    }
    const struct ranging_can_raw *f = &r->next.frame;
    struct canfd_frame out;
    memset(&out, 0, sizeof(out));
    out.can_id = f->can_id;
    out.len = f->len;
    out.flags = f->fd ? f->fd_flags : 0;
    memcpy(out.data, f->data, f->len);
    if (ranging_socketcan_write(r->fd_out, &out, f->fd) < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS) {
        return 1;
      }
      snprintf(err, errlen, "%s:%u: cannot write the frame: %s", r->path, r->line_no, strerror(errno));
      return -1;
    }
    r->pending = false;
    r->count++;
  }
}

uint32_t ranging_can_replay_count(const struct ranging_can_replay *r)
{
  return r->count;
}

void ranging_can_replay_close(struct ranging_can_replay *r)
{
  if (r == NULL) {
    return;
  }
  fclose(r->log);
  free(r);
}
