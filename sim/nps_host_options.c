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
 * @file nps_host_options.c
 * Command line of the NPS-style host.
 */

#include "nps_host_options.h"
#include "nps_host_threads.h"

#include <errno.h>
#include <getopt.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Default correlation time of --ins-drift [s] (nps_ins_drift.h) */
#define NPS_HOST_INS_DRIFT_TAU 10.0

/** Range of --pose-rate [Hz]; whether a rate fits the airframe's step rate is checked when the run starts. */
#define NPS_HOST_POSE_RATE_MIN 1e-3
#define NPS_HOST_POSE_RATE_MAX 1e6

/** Largest swarm the host accepts (the benchmarks run 1000 copters; aircraft id 0 is reserved). */
#define NPS_HOST_MAX_VEHICLES 4096

static void usage(const char *prog)
{
  fprintf(stderr,
          "usage: %s [--vehicles N] [--seed S] [--duration SECONDS] [--out DIR] [--arena FILE]\n"
          "       [--sensor-model FILE|TEXT] [--ranging-replay CANDUMP.log] [--threads N] [--no-logs] [--realtime]\n"
          "       [--ins-drift SD[,TAU]] [--pose-rate HZ] [--quiet]\n"
          "  --vehicles N        copters in the arena, 1..%d (default 4)\n"
          "  --seed S            seed of every random stream (default 1)\n"
          "  --duration SECONDS  simulated time (default 60)\n"
          "  --out DIR           folder for readings.csv, poses.csv and walls.csv (default build/sim)\n"
          "  --arena FILE        arena XML (default: the airframe's NPS_ARENA_FILE)\n"
          "  --sensor-model M    sensor model file or inline model (default: the airframe's NPS_SENSOR_MODEL)\n"
          "  --ranging-replay L  feed a candump -l log of the ranging units (the bus of its first frame) to the\n"
          "                      copters (node id = aircraft id)\n"
          "                      instead of simulated ranging; what is delivered goes to ranging_replay.csv\n"
          "  --threads N         threads for the copters' modules, 1..%d (default: the usable cores, but 1 below\n"
          "                      %d copters); the logs are the same for every N\n"
          "  --ins-drift SD[,TAU] the copters' position estimates drift: velocity error SD m/s per axis, correlated\n"
          "                      over TAU s (default 10), integrated (nps_ins_drift.h; default: no drift)\n"
          "  --pose-rate HZ      rows of poses.csv per copter and second (default: the airframe's\n"
          "                      NPS_POSE_LOG_FREQUENCY, else 10): a whole number of steps apart, so the step rate\n"
          "                      (the airframe's PERIODIC_FREQUENCY) divided by a whole number\n"
          "  --no-logs           write no logs (faster batch runs)\n"
          "  --realtime          run at wall-clock speed instead of as fast as possible\n"
          "  --quiet             no progress display\n", prog, NPS_HOST_MAX_VEHICLES, NPS_HOST_THREADS_MAX,
          NPS_HOST_THREADS_MIN_VEHICLES);
}

static int parse_number(const char *name, const char *text, double min, double max, double *value)
{
  char *end;
  errno = 0;
  *value = strtod(text, &end);
  if (errno != 0 || end == text || *end != '\0' || !(*value >= min && *value <= max)) {
    fprintf(stderr, "error: --%s '%s': expected a number in [%g, %g]\n", name, text, min, max);
    return -1;
  }
  return 0;
}

/** --ins-drift SD[,TAU]: the velocity error's sd [m/s] and, optionally, its correlation time [s]. */
static int parse_drift(const char *text, struct nps_ins_drift_params *drift)
{
  char sd_text[64];
  const char *comma = strchr(text, ',');
  const size_t sd_len = comma != NULL ? (size_t)(comma - text) : strlen(text);
  if (sd_len >= sizeof(sd_text)) {
    fprintf(stderr, "error: --ins-drift '%s': expected SD[,TAU]\n", text);
    return -1;
  }
  memcpy(sd_text, text, sd_len);
  sd_text[sd_len] = '\0';
  if (parse_number("ins-drift (SD, m/s)", sd_text, 0, 10, &drift->sd_mps) < 0) {
    return -1;
  }
  return comma == NULL ? 0 : parse_number("ins-drift (TAU, s)", comma + 1, 1e-3, 1e6, &drift->tau_s);
}

/** A whole number in decimal digits only (no sign, point, exponent or hex prefix), within [min, max]. */
static int parse_count(const char *name, const char *text, unsigned long long min, unsigned long long max,
                       unsigned long long *value)
{
  char *end;
  errno = 0;
  *value = strtoull(text, &end, 10);
  if (text[0] < '0' || text[0] > '9' || errno != 0 || *end != '\0' || *value < min || *value > max) {
    fprintf(stderr, "error: --%s '%s': expected a whole number in [%llu, %llu]\n", name, text, min, max);
    return -1;
  }
  return 0;
}

int nps_host_parse_options(int argc, char **argv, struct nps_host_options *opt)
{
  static const struct option longopts[] = {
    {"vehicles", required_argument, NULL, 'n'},
    {"seed", required_argument, NULL, 's'},
    {"duration", required_argument, NULL, 'd'},
    {"out", required_argument, NULL, 'o'},
    {"arena", required_argument, NULL, 'a'},
    {"sensor-model", required_argument, NULL, 'm'},
    {"no-logs", no_argument, NULL, 'L'},
    {"ranging-replay", required_argument, NULL, 'R'},
    {"threads", required_argument, NULL, 't'},
    {"realtime", no_argument, NULL, 'r'},
    {"quiet", no_argument, NULL, 'q'},
    {"ins-drift", required_argument, NULL, 'D'},
    {"pose-rate", required_argument, NULL, 'P'},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
  };
  *opt = (struct nps_host_options) {
    .vehicles = 4, .seed = 1, .duration_s = 60.0, .out_dir = "build/sim",
    .ins_drift = { .sd_mps = 0.0, .tau_s = NPS_HOST_INS_DRIFT_TAU },
  };
  double value;
  unsigned long long count;
  int c;
  while ((c = getopt_long(argc, argv, "", longopts, NULL)) != -1) {
    switch (c) {
      case 'n':
        if (parse_count("vehicles", optarg, 1, NPS_HOST_MAX_VEHICLES, &count) < 0) {
          usage(argv[0]);
          return -1;
        }
        opt->vehicles = (unsigned)count;
        break;
      case 's':
        if (parse_count("seed", optarg, 0, UINT64_MAX, &count) < 0) {
          usage(argv[0]);
          return -1;
        }
        opt->seed = count;
        break;
      case 'd':
        if (parse_number("duration", optarg, 0, 1e9, &value) < 0) {
          usage(argv[0]);
          return -1;
        }
        opt->duration_s = value;
        break;
      case 'o':
        opt->out_dir = optarg;
        break;
      case 'a':
        opt->arena_file = optarg;
        break;
      case 'm':
        opt->sensor_model = optarg;
        break;
      case 't':
        if (parse_count("threads", optarg, 1, NPS_HOST_THREADS_MAX, &count) < 0) {
          usage(argv[0]);
          return -1;
        }
        opt->threads = (unsigned)count;
        break;
      case 'L':
        opt->no_logs = true;
        break;
      case 'R':
        opt->ranging_replay = optarg;
        break;
      case 'r':
        opt->realtime = true;
        break;
      case 'q':
        opt->quiet = true;
        break;
      case 'D':
        if (parse_drift(optarg, &opt->ins_drift) < 0) {
          usage(argv[0]);
          return -1;
        }
        break;
      case 'P':
        if (parse_number("pose-rate", optarg, NPS_HOST_POSE_RATE_MIN, NPS_HOST_POSE_RATE_MAX, &value) < 0) {
          usage(argv[0]);
          return -1;
        }
        opt->pose_rate_hz = value;
        break;
      case 'h':
        usage(argv[0]);
        return 1;
      default:
        usage(argv[0]);
        return -1;
    }
  }
  if (optind != argc) {
    fprintf(stderr, "error: unexpected argument '%s'\n", argv[optind]);
    usage(argv[0]);
    return -1;
  }
  return 0;
}
