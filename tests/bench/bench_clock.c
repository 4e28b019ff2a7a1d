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
 * @file bench_clock.c
 * The processor's effective clock, measured the moment it runs: the rate of a chain of dependent integer
 * additions of a register to a register, each of which must wait for the one before (latency one cycle on every
 * x86-64 and ARMv8 core). The increment is a register, not a constant: on the development machine's Xeon a
 * chain of `add $1` ran at ~4 per cycle (the core folds constant additions), which would read as 12 GHz.
 *
 *   bench_clock [--reps 3] [--adds 1e8]
 *
 * prints clock_ghz, the median of the repetitions [1e9 additions per wall-clock second]: the clock the core
 * really runs at, where a virtual machine's /proc/cpuinfo may show only a nominal one. tools/finken/bench/host.py
 * measures it just before and just after each timed host run. It does not see the other tenants of a shared
 * core: a chain of single additions needs one execution unit, the host's code many (docs/performance.md, "What
 * bounds each figure").
 */

#include "bench_common.h"

#include <stdint.h>

/** Additions per loop turn: the loop's own counter and branch run beside the chain and never set its pace. */
#define BENCH_CLOCK_UNROLL 8

/** One dependent addition of `step` to x: the empty asm makes x an opaque register value, so the compiler can
 * neither fold the additions into one nor vectorise them. */
#define BENCH_CLOCK_ADD(x, step) do { (x) += (step); __asm__ volatile("" : "+r"(x)); } while (0)

/** Effective clock [GHz] over `turns` x BENCH_CLOCK_UNROLL additions. */
static double clock_ghz(uint64_t turns)
{
  uint64_t x = 0, step = 1;
  __asm__ volatile("" : "+r"(step));   /* a value the compiler cannot see: added from a register */
  const double t0 = bench_now_s();
  for (uint64_t i = 0; i < turns; i++) {
    BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step);
    BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step); BENCH_CLOCK_ADD(x, step);
  }
  const double seconds = bench_now_s() - t0;
  if (x != turns * BENCH_CLOCK_UNROLL || !(seconds > 0.0)) {
    bench_die("bench_clock", "the addition chain did not run as written");
  }
  return 1e-9 * (double)x / seconds;
}

int main(int argc, char **argv)
{
  const int reps = bench_reps(argc, argv, 3);
  const double adds = bench_option(argc, argv, "adds", 1e8);
  if (!(adds >= BENCH_CLOCK_UNROLL && adds <= 1e12)) {
    bench_die("--adds", "expected 8 .. 1e12 additions");
  }
  const uint64_t turns = (uint64_t)(adds / BENCH_CLOCK_UNROLL);
  double ghz[BENCH_MAX_REPS];
  for (int k = 0; k < reps; k++) {
    ghz[k] = clock_ghz(turns);
  }
  bench_report("clock_ghz", ghz, reps, "GHz");
  return 0;
}
