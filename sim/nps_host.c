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
 * airframe names (generated/modules.h), with that copter's state selected. The per-copter parts run on
 * --threads threads, each on chunks of copters (nps_host_threads.h), in one phase per step: a copter's
 * autopilot and then its flight model's next step, whose pose the simulator takes at the next world step
 * (nps_host_world.h), so that a step needs a single meeting of the threads.
 */

#include "nps_host_options.h"
#include "nps_host_outputs.h"
#include "nps_host_ranging_replay.h"
#include "nps_host_threads.h"
#include "nps_host_world.h"

#include "generated/airframe.h"
#include "generated/modules.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

/** SIGINT or SIGTERM received: the run ends at the next step that logs poses, every log complete. */
static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int signum)
{
  stop_signal = signum;
}

/** A run that could not start: its staged files go, the previous run's stay. */
static int failed_start(struct nps_host_world *world)
{
  if (world != NULL) {
    nps_host_world_close(world);
  }
  nps_host_outputs_discard();
  return EXIT_FAILURE;
}

/** The first log whose writes failed, NULL when none did. */
static const char *write_error(const struct nps_host_world *world)
{
  const char *failed = nps_host_world_write_error(world);
  return failed != NULL ? failed : nps_host_ranging_replay_write_error();
}

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

/** What the copters of a host step share. */
struct host_step {
  struct nps_host_world *world;
  uint32_t step;    ///< the modules' periodic counter (it wraps, as Paparazzi's does)
  bool log_poses;   ///< the copters' poses are logged in this step
  bool published;   ///< the copters' states already went to their modules in this step
  bool last;        ///< the last step: no flight model step after it
};

/** Copter v's state to its modules (on the calling thread). */
static void publish_copter(void *ctx, unsigned v)
{
  const struct host_step *s = ctx;
  nps_host_world_publish(s->world, v, s->log_poses);
}

/** Copter v in a host step (on the calling thread): its state to its modules, its modules, its flight model. */
static void run_copter(void *ctx, unsigned v)
{
  const struct host_step *s = ctx;
  if (s->published) {
    pprz_vehicle_select(v);   /* its modules run on its state */
  } else {
    publish_copter(ctx, v);   /* selects v */
  }
  modules_periodic_task(s->step);
  modules_event_task();
  if (!s->last) {
    nps_host_world_advance(s->world, v);
  }
}

/** Copter v's first flight model step, from its start pose. */
static void first_advance(void *world, unsigned v)
{
  nps_host_world_advance(world, v);
}

int main(int argc, char **argv)
{
  struct nps_host_options opt;
  const int parsed = nps_host_parse_options(argc, argv, &opt);
  if (parsed != 0) {
    return parsed > 0 ? EXIT_SUCCESS : 2;
  }
  const double dt_s = 1.0 / PERIODIC_FREQUENCY;
  struct nps_host_world world;
  signal(SIGINT, on_stop_signal);   /* from here on, a signal ends the run at a step boundary (or before it starts) */
  signal(SIGTERM, on_stop_signal);
  if (nps_host_outputs_begin(opt.out_dir) < 0) {
    return EXIT_FAILURE;
  }
  if (nps_host_world_open(&world, &opt, dt_s) < 0) {
    return failed_start(NULL);
  }
  for (unsigned v = 0; v < opt.vehicles; v++) {
    pprz_vehicle_select(v);
    modules_init();
  }
  if (opt.ranging_replay != NULL &&
      nps_host_ranging_replay_open(opt.ranging_replay, nps_host_outputs_staged("ranging_replay.csv"), opt.vehicles) < 0) {
    return failed_start(&world);
  }
  const uint64_t log_bytes = (uint64_t)(nps_host_world_log_bytes_per_s(&world) * opt.duration_s);
  if (nps_host_outputs_fit(log_bytes) < 0) {
    nps_host_ranging_replay_close();
    return failed_start(&world);
  }
  struct nps_host_threads *threads = nps_host_threads_start(
      opt.threads != 0 ? opt.threads : nps_host_threads_default(opt.vehicles), opt.vehicles);
  if (threads == NULL) {
    nps_host_ranging_replay_close();
    return failed_start(&world);
  }
  if (opt.threads == 0) {   /* the default count: one thread when the others would only wait (a busy machine) */
    nps_host_threads_adapt(threads);
  }

  const uint64_t steps = (uint64_t)llround(opt.duration_s * PERIODIC_FREQUENCY);
  struct timespec start;
  clock_gettime(CLOCK_MONOTONIC, &start);
  int last_shown = -1;
  if (!opt.quiet) {
    fprintf(stderr, "%s: %u copters, %.1f s simulated at %g Hz (%llu steps), seed %llu, %u thread(s)%s\n",
            AIRFRAME_NAME, opt.vehicles, opt.duration_s, (double)PERIODIC_FREQUENCY, (unsigned long long)steps,
            (unsigned long long)opt.seed, nps_host_threads_count(threads), opt.threads == 0 ? " (or 1 if faster)" : "");
    if (log_bytes > 1000000000u) {   /* a large run says what it will write */
      fprintf(stderr, "%s: about %.1f GB of logs to %s\n", AIRFRAME_NAME, log_bytes * 1e-9, opt.out_dir);
    }
  }
  int rc = EXIT_SUCCESS;
  nps_host_threads_for_each(threads, first_advance, &world);   /* writes no log row */
  for (uint64_t step = 0; step < steps && rc == EXIT_SUCCESS; step++) {
    const double t_s = (step + 1) * dt_s;
    struct host_step s = { .world = &world, .step = (uint32_t)step, .log_poses = nps_host_world_step(&world, t_s),
                           .last = step + 1 == steps };
    sys_time_host_set(t_s);
    int logged = 0;
    if (opt.ranging_replay != NULL) {
      /* recorded distances reach the modules after every copter's new state, as the simulated ones do */
      logged = nps_host_threads_for_each(threads, publish_copter, &s);
      s.published = true;
      if (nps_host_ranging_replay_step(t_s) < 0) {
        rc = EXIT_FAILURE;
        break;
      }
    }
    if ((nps_host_threads_for_each(threads, run_copter, &s) | logged) < 0) {
      fprintf(stderr, "error: out of memory for the log rows of step %llu\n", (unsigned long long)step);
      rc = EXIT_FAILURE;
    }
    if (s.log_poses || opt.no_logs) {   /* a step where every log has its rows: stop here if need be */
      const char *failed = write_error(&world);
      if (failed != NULL) {
        fprintf(stderr, "\nerror: writing %s failed at %.2f s (disk full?): the run stops, its logs end there\n",
                failed, t_s);
        rc = EXIT_FAILURE;
      } else if (stop_signal != 0) {
        fprintf(stderr, "\n%s at %.2f s: the run stops, its logs end there\n",
                stop_signal == SIGINT ? "SIGINT" : "SIGTERM", t_s);
        break;
      }
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
  if (nps_host_ranging_replay_close() < 0) {
    rc = EXIT_FAILURE;
  }
  if (nps_host_world_close(&world) < 0) {
    rc = EXIT_FAILURE;
  }
  if (nps_host_outputs_commit() < 0) {   /* also after a write error: the complete rows are kept */
    rc = EXIT_FAILURE;
  }
  return stop_signal != 0 && rc == EXIT_SUCCESS ? 128 + stop_signal : rc;
}
