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
 * @file nps_host.c
 * NPS-style host: N copters in one arena, lock-step and deterministic for a seed.
 *
 * Each main-loop step follows Paparazzi NPS (nps_main_run_sim_step): the flight model of every copter,
 * then the simulator hooks (sensors, walls), then every copter's autopilot, i.e. the modules the
 * airframe names (generated/modules.h), with that copter's state selected; the autopilots run on
 * --threads threads, each on a block of copters (nps_host_threads.h).
 */

#include "nps_host_options.h"
#include "nps_host_ranging_replay.h"
#include "nps_host_threads.h"
#include "nps_host_world.h"

#include "generated/airframe.h"
#include "generated/modules.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static void sleep_until(const struct timespec *start, double elapsed_s)
{
  struct timespec target = *start;
  target.tv_sec += (time_t)elapsed_s;
  target.tv_nsec += (long)((elapsed_s - floor(elapsed_s)) * 1e9);
  if (target.tv_nsec >= 1000000000L) {
    target.tv_sec++;
    target.tv_nsec -= 1000000000L;
  }
  clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &target, NULL);
}

/** Progress on stderr: a refreshed line on a terminal, every 10% otherwise. */
static void show_progress(double t_s, double duration_s, int *last_shown)
{
  const int percent = duration_s > 0.0 ? (int)(100.0 * t_s / duration_s) : 100;
  const int every = isatty(STDERR_FILENO) ? 1 : 10;
  if (percent / every != *last_shown / every) {
    fprintf(stderr, isatty(STDERR_FILENO) ? "\r  simulated %.1f of %.1f s (%d%%)" : "  simulated %.1f of %.1f s (%d%%)\n",
            t_s, duration_s, percent);
    *last_shown = percent;
  }
}

/** The autopilot of copter v in step *(uint32_t *)step: its modules, with its state selected (on the calling thread). */
static void run_modules(void *step, unsigned v)
{
  pprz_vehicle_select(v);
  modules_periodic_task(*(uint32_t *)step);
  modules_event_task();
}

int main(int argc, char **argv)
{
  struct nps_host_options opt;
  const int parsed = nps_host_parse_options(argc, argv, &opt);
  if (parsed != 0) {
    return parsed > 0 ? EXIT_SUCCESS : 2;
  }
  struct nps_host_world world;
  if (nps_host_world_open(&world, &opt) < 0) {
    return EXIT_FAILURE;
  }
  for (unsigned v = 0; v < opt.vehicles; v++) {
    pprz_vehicle_select(v);
    modules_init();
  }
  struct nps_host_threads *threads = nps_host_threads_start(
      opt.threads != 0 ? opt.threads : nps_host_threads_default(opt.vehicles), opt.vehicles);
  if (threads == NULL ||
      (opt.ranging_replay != NULL && nps_host_ranging_replay_open(opt.ranging_replay, opt.out_dir, opt.vehicles) < 0)) {
    nps_host_threads_stop(threads);
    nps_host_world_close(&world);
    return EXIT_FAILURE;
  }

  const double dt_s = 1.0 / PERIODIC_FREQUENCY;
  const uint32_t steps = (uint32_t)llround(opt.duration_s * PERIODIC_FREQUENCY);
  struct timespec start;
  clock_gettime(CLOCK_MONOTONIC, &start);
  int last_shown = -1;
  if (!opt.quiet) {
    fprintf(stderr, "%s: %u copters, %.1f s simulated at %g Hz, seed %llu, %u thread(s)\n", AIRFRAME_NAME,
            opt.vehicles, opt.duration_s, (double)PERIODIC_FREQUENCY, (unsigned long long)opt.seed,
            nps_host_threads_count(threads));
  }
  int rc = EXIT_SUCCESS;
  for (uint32_t step = 0; step < steps && rc == EXIT_SUCCESS; step++) {
    const double t_s = (step + 1) * dt_s;
    const int logged = nps_host_world_step(&world, threads, t_s, dt_s);
    sys_time_host_set(t_s);
    if (opt.ranging_replay != NULL && nps_host_ranging_replay_step(t_s) < 0) {
      rc = EXIT_FAILURE;
      break;
    }
    if ((nps_host_threads_for_each(threads, run_modules, &step) | logged) < 0) {
      fprintf(stderr, "error: out of memory for the log rows of step %u\n", step);
      rc = EXIT_FAILURE;
    }
    if (opt.realtime) {
      sleep_until(&start, t_s);
    }
    if (!opt.quiet) {
      show_progress(t_s, opt.duration_s, &last_shown);
    }
  }
  if (!opt.quiet && isatty(STDERR_FILENO)) {
    fputc('\n', stderr);
  }
  nps_host_threads_stop(threads);
  if (opt.ranging_replay != NULL) {
    nps_host_ranging_replay_close();
  }
  return nps_host_world_close(&world) < 0 ? EXIT_FAILURE : rc;
}
