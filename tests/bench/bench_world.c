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
 * @file bench_world.c
 * The simulator side of the host alone (nps_swarm.h), for N copters laid out at a fixed density: what the
 * sonar pipeline, the ranging pipeline and the walls cost, per reading and per copter-step, without the
 * modules and the flight model.
 *
 *   bench_world --arena FILE --model FILE --vehicles N [--seconds 20] [--reps 5] [--log DIR] [--suffix _4]
 *
 * Each 10 ms step, like the example airframe at PERIODIC_FREQUENCY 100: every copter moves on its 0.5 m
 * circle (bench_common.h) and gets its pose; nps_swarm_step (copter index, walls, wall snapshot); every copter's
 * sonar ring takes one slot of its round robin as sonar_array does at 20 Hz per sonar (fire one sonar, read
 * the one fired two slots earlier: ray cast, facing emitters and pulses in flight, the sonar chain); every tenth
 * step every copter measures its ranging peers (10 Hz: line-of-sight cast, the ranging chain's GMM).
 * With --log the range log and the wall snapshots are written to DIR (readings.csv, walls.csv).
 *
 * Figures (suffix appended): sonar_readings_per_s, ranging_readings_per_s, walls_us_per_step,
 * world_us_per_copter_step (all three phases over copters x steps).
 */

#include "bench_common.h"
#include "nps_raycast.h"
#include "nps_swarm.h"

#include <stdint.h>

/** Host step rate [Hz] (example airframe: PERIODIC_FREQUENCY 100). */
#define BENCH_WORLD_STEP_HZ 100
/** Sonar readings per second of each sonar (sonar_array: SONAR_ARRAY_RATE). */
#define BENCH_WORLD_SONAR_HZ 20
/** Listening window in round-robin slots (sonar_array: SONAR_ARRAY_READ_DELAY). */
#define BENCH_WORLD_READ_DELAY 2
/** Ranging passes per second (virtual_ranging: periodic freq 10). */
#define BENCH_WORLD_RANGING_HZ 10

/** sonar_array's firing order (sonar_array_schedule.c). */
static const unsigned firing_order[NPS_SONAR_COUNT] = {
  NPS_SONAR_FRONT, NPS_SONAR_BACK, NPS_SONAR_RIGHT, NPS_SONAR_LEFT, NPS_SONAR_DOWN
};

struct world_times {
  double sonar_s, ranging_s, walls_s;
  long sonar_readings, ranging_readings, steps;
};

static void count_reading(void *ctx, uint16_t peer_id, double distance_m)
{
  (void)peer_id;
  (void)distance_m;
  (*(long *)ctx)++;
}

/** Simulate from step *k for `steps` steps, adding up the time of each phase. */
static void run_steps(unsigned n, const double *centre_m, long *k, long steps, struct world_times *wt)
{
  const struct nps_arena *a = nps_swarm_arena();
  const double dt_s = 1.0 / BENCH_WORLD_STEP_HZ;
  const long slot_every = BENCH_WORLD_STEP_HZ / (BENCH_WORLD_SONAR_HZ * NPS_SONAR_COUNT);
  const long ranging_every = BENCH_WORLD_STEP_HZ / BENCH_WORLD_RANGING_HZ;
  for (long end = *k + steps; *k < end; (*k)++) {
    const double t_s = (double)(*k + 1) * dt_s;
    for (unsigned v = 0; v < n; v++) {
      double pos_m[3], yaw_rad, speed_mps;
      bench_circle_pose(centre_m, (int)v, a->flight_height_m, t_s, pos_m, &yaw_rad, &speed_mps);
      nps_swarm_set_pose(v, pos_m, yaw_rad, speed_mps);
    }
    const double t0 = bench_now_s();
    if (nps_swarm_step(t_s) < 0) {
      bench_die("nps_swarm_step", "failed");
    }
    const double t1 = bench_now_s();
    if (*k % slot_every == 0) {
      const long slot = *k / slot_every;
      const unsigned fire = firing_order[slot % NPS_SONAR_COUNT];
      const unsigned read = firing_order[(slot + NPS_SONAR_COUNT - BENCH_WORLD_READ_DELAY) % NPS_SONAR_COUNT];
      const double fired_s = t_s - BENCH_WORLD_READ_DELAY * slot_every * dt_s;
      for (unsigned v = 0; v < n; v++) {
        nps_swarm_sonar_trigger(v, fire, t_s);
        if (slot >= BENCH_WORLD_READ_DELAY) {
          nps_swarm_sonar_read(v, read, fired_s, t_s);
          wt->sonar_readings++;
        }
      }
    }
    const double t2 = bench_now_s();
    if (*k % ranging_every == 0) {
      for (unsigned v = 0; v < n; v++) {
        nps_swarm_ranging_measure(v, t_s, count_reading, &wt->ranging_readings);
      }
    }
    const double t3 = bench_now_s();
    wt->walls_s += t1 - t0;
    wt->sonar_s += t2 - t1;
    wt->ranging_s += t3 - t2;
    wt->steps++;
  }
}

int main(int argc, char **argv)
{
  const char *arena = bench_option_text(argc, argv, "arena", NULL);
  const char *model = bench_option_text(argc, argv, "model", NULL);
  const unsigned n = (unsigned)bench_option(argc, argv, "vehicles", 0);
  if (arena == NULL || model == NULL || n < 1) {
    bench_die("usage", "bench_world --arena FILE --model FILE --vehicles N [--seconds S] [--reps R] [--log DIR] "
              "[--suffix TEXT]");
  }
  const int reps = bench_reps(argc, argv, 5);
  const double seconds = bench_option(argc, argv, "seconds", 20.0);
  const char *log_dir = bench_option_text(argc, argv, "log", NULL);
  const char *suffix = bench_option_text(argc, argv, "suffix", "");
  char readings[4096], walls[4096], err[512];
  snprintf(readings, sizeof(readings), "%s/readings.csv", log_dir ? log_dir : ".");
  snprintf(walls, sizeof(walls), "%s/walls.csv", log_dir ? log_dir : ".");
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = n, .arena_file = arena, .sensor_model = model,
    .readings_path = log_dir ? readings : NULL, .walls_path = log_dir ? walls : NULL, .walls_period_s = 1.0,
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    bench_die(arena, err);
  }
  double *centre_m = malloc(2 * (size_t)n * sizeof(*centre_m));
  if (centre_m == NULL) {
    bench_die("bench_world", "out of memory");
  }
  bench_grid_points(nps_swarm_arena(), (int)n, centre_m);
  for (unsigned v = 0; v < n; v++) {
    nps_swarm_sonar_attach(v, 1.0 / BENCH_WORLD_SONAR_HZ);
    nps_swarm_ranging_equip(v);
  }
  long k = 0;
  struct world_times warm = {0};
  run_steps(n, centre_m, &k, (long)(0.1 * seconds * BENCH_WORLD_STEP_HZ) + 1, &warm);
  double sonar[BENCH_MAX_REPS], ranging[BENCH_MAX_REPS], walls_us[BENCH_MAX_REPS], world_us[BENCH_MAX_REPS];
  for (int r = 0; r < reps; r++) {
    struct world_times wt = {0};
    run_steps(n, centre_m, &k, (long)(seconds * BENCH_WORLD_STEP_HZ), &wt);
    sonar[r] = (double)wt.sonar_readings / wt.sonar_s;
    ranging[r] = (double)wt.ranging_readings / wt.ranging_s;
    walls_us[r] = 1e6 * wt.walls_s / (double)wt.steps;
    world_us[r] = 1e6 * (wt.walls_s + wt.sonar_s + wt.ranging_s) / ((double)wt.steps * n);
    if (r == 0) {
      fprintf(stderr, "bench_world%s: %u copters, per copter and second: %.1f sonar, %.1f ranging readings\n",
              suffix, n, (double)wt.sonar_readings * BENCH_WORLD_STEP_HZ / ((double)wt.steps * n),
              (double)wt.ranging_readings * BENCH_WORLD_STEP_HZ / ((double)wt.steps * n));
    }
  }
  char name[128];
  snprintf(name, sizeof(name), "sonar_readings_per_s%s", suffix);
  bench_report(name, sonar, reps, "1/s");
  snprintf(name, sizeof(name), "ranging_readings_per_s%s", suffix);
  bench_report(name, ranging, reps, "1/s");
  snprintf(name, sizeof(name), "walls_us_per_step%s", suffix);
  bench_report(name, walls_us, reps, "us");
  snprintf(name, sizeof(name), "world_us_per_copter_step%s", suffix);
  bench_report(name, world_us, reps, "us");
  free(centre_m);
  if (nps_swarm_free() < 0) {
    bench_die("bench_world", "writing the logs failed");
  }
  return 0;
}
