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
 * @file bench_spawn.c
 * Run one command and report its wall-clock time and its own peak resident memory.
 *
 *   bench_spawn RESULT_FILE COMMAND [ARGS...]
 *
 * writes {"wall_s": ..., "peak_rss_kb": ..., "exit_status": ...} to RESULT_FILE, and exits with 0 when it could
 * run the command (whatever the command's status). Why a C launcher: Linux counts the memory a child had
 * before exec in its ru_maxrss, so a child forked straight from the Python benchmark driver would report the
 * driver's ~100 MB; forked from this small program, the figure is the command's own.
 */

#include "bench_common.h"

#include <errno.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

int main(int argc, char **argv)
{
  if (argc < 3) {
    bench_die("usage", "bench_spawn RESULT_FILE COMMAND [ARGS...]");
  }
  FILE *result = fopen(argv[1], "w");
  if (result == NULL) {
    bench_die(argv[1], strerror(errno));
  }
  const double t0 = bench_now_s();
  const pid_t pid = fork();
  if (pid < 0) {
    bench_die("fork", strerror(errno));
  }
  if (pid == 0) {
    execvp(argv[2], argv + 2);
    fprintf(stderr, "bench_spawn: %s: %s\n", argv[2], strerror(errno));
    _exit(127);
  }
  int status;
  struct rusage usage;
  if (wait4(pid, &status, 0, &usage) < 0) {
    bench_die("wait4", strerror(errno));
  }
  const double wall_s = bench_now_s() - t0;
  const int exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  fprintf(result, "{\"wall_s\": %.9g, \"peak_rss_kb\": %ld, \"exit_status\": %d}\n", wall_s, usage.ru_maxrss,
          exit_status);
  return fclose(result) == 0 ? 0 : 1;
}
