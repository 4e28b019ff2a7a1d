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
 * @file nps_host_outputs.c
 * Staged outputs of a host run (see nps_host_outputs.h).
 */

#define _GNU_SOURCE   /* memrchr */
#include "nps_host_outputs.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

static const char *const names[] = NPS_HOST_OUTPUT_NAMES;
#define OUTPUTS (sizeof(names) / sizeof(names[0]))

static struct {
  char dir[4096];
  char staged[OUTPUTS][4096 + 64];
  char final[OUTPUTS][4096 + 64];
} outputs;

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

int nps_host_outputs_begin(const char *out_dir)
{
  if (snprintf(outputs.dir, sizeof(outputs.dir), "%s", out_dir) >= (int)sizeof(outputs.dir) || make_dirs(out_dir) < 0) {
    fprintf(stderr, "error: cannot create %s: %s\n", out_dir, strerror(errno ? errno : ENAMETOOLONG));
    return -1;
  }
  for (size_t i = 0; i < OUTPUTS; i++) {
    snprintf(outputs.staged[i], sizeof(outputs.staged[i]), "%s/.%s.partial", out_dir, names[i]);
    snprintf(outputs.final[i], sizeof(outputs.final[i]), "%s/%s", out_dir, names[i]);
    unlink(outputs.staged[i]);
  }
  return 0;
}

const char *nps_host_outputs_staged(const char *name)
{
  for (size_t i = 0; i < OUTPUTS; i++) {
    if (strcmp(names[i], name) == 0) {
      return outputs.staged[i];
    }
  }
  return NULL;
}

int nps_host_outputs_fit(uint64_t bytes)
{
  struct statvfs fs;
  if (statvfs(outputs.dir, &fs) < 0) {
    return 0;   /* unknown: the writes will tell */
  }
  const uint64_t free_bytes = (uint64_t)fs.f_bavail * fs.f_frsize;
  if (bytes + bytes / 20 <= free_bytes) {
    return 0;
  }
  fprintf(stderr, "error: this run would write about %.3g GB of logs to %s, which has %.3g GB free: use --no-logs, "
          "a shorter --duration, fewer --vehicles or another --out\n", bytes * 1e-9, outputs.dir, free_bytes * 1e-9);
  return -1;
}

/** Cut the file after its last newline (a row cut by a failed write or a kill is not kept). */
static int cut_after_last_row(const char *path)
{
  const int fd = open(path, O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    return -1;
  }
  off_t end = lseek(fd, 0, SEEK_END);
  char block[4096];
  while (end > 0) {
    const off_t start = end > (off_t)sizeof(block) ? end - (off_t)sizeof(block) : 0;
    const ssize_t n = pread(fd, block, (size_t)(end - start), start);
    if (n <= 0) {
      break;
    }
    const char *last = memrchr(block, '\n', (size_t)n);
    if (last != NULL) {
      end = start + (last - block) + 1;
      break;
    }
    end = start;
  }
  const int rc = ftruncate(fd, end);
  close(fd);
  return rc;
}

int nps_host_outputs_commit(void)
{
  int rc = 0;
  for (size_t i = 0; i < OUTPUTS; i++) {
    if (access(outputs.staged[i], F_OK) != 0) {
      unlink(outputs.final[i]);   /* an earlier run's file this run did not write would mislead */
    } else if (cut_after_last_row(outputs.staged[i]) < 0 || rename(outputs.staged[i], outputs.final[i]) < 0) {
      fprintf(stderr, "error: cannot put %s in place: %s\n", outputs.final[i], strerror(errno));
      rc = -1;
    }
  }
  return rc;
}

void nps_host_outputs_discard(void)
{
  for (size_t i = 0; i < OUTPUTS; i++) {
    unlink(outputs.staged[i]);
  }
}
