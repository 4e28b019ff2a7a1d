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
 * @file nps_host_threads.c
 * The per-copter phases of a host step on several threads (see nps_host_threads.h).
 *
 * Work sharing: the copters of a phase go out in chunks, in copter order, to whichever thread asks next
 * (guided: a chunk is the remaining copters over twice the threads, at least `min_chunk`, i.e.
 * NPS_HOST_THREADS_MIN_CHUNK, or a thread's share of a smaller swarm), so
 * that a thread whose copters cost more (denser neighbourhoods) does not keep the others waiting. A chunk's
 * log rows go to its own spool, and the main thread appends the spools in chunk, i.e. copter, order.
 *
 * Synchronisation, twice per phase: the main thread bumps `generation` to start a phase, each worker
 * decrements `remaining` when its block is done. A waiting thread first spins (the other side is usually
 * about to finish: a phase of 1000 copters lasts well under a millisecond) and then sleeps on a futex; the
 * `*_asleep` counters let the waking side skip the system call when nobody sleeps. The sequentially
 * consistent increment of a counter before the futex's check of the word, and the store of the word
 * before the load of the counter, make it impossible for both sides to miss each other (Dekker).
 */

#define _GNU_SOURCE   /* sched_getaffinity, CPU_COUNT */

#include "nps_host_threads.h"

#include "nps_csv.h"

#include <limits.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#ifndef NPS_HOST_THREADS_SPIN
/**
 * Polls of a word before a waiting thread sleeps in the kernel: about 150 us on the CI machine (a pause
 * takes 15 ns there), longer than the single-threaded world step of 1000 copters (~100 us), so that the
 * workers wait through it without a futex round trip (tens of microseconds in a virtual machine). With
 * 4000 polls a 1000-copter run made one futex wait per step, with 40000 almost none.
 */
#define NPS_HOST_THREADS_SPIN 10000
#endif
#ifndef NPS_HOST_THREADS_MIN_CHUNK
/** Fewest copters of a chunk (but the last): a claim costs an atomic operation on a shared line. */
#define NPS_HOST_THREADS_MIN_CHUNK 8
#endif
#ifndef NPS_HOST_THREADS_WINDOW
/** Steps per measurement of the setting in use by the adaptive choice (nps_host_threads_adapt). */
#define NPS_HOST_THREADS_WINDOW 512
#endif
#ifndef NPS_HOST_THREADS_PROBE
/** Steps per trial of the other setting: short, for it may be much slower (2 threads on a busy 2-core machine). */
#define NPS_HOST_THREADS_PROBE 32
#endif
#ifndef NPS_HOST_THREADS_REPROBE
/** Windows between two trials of the setting not in use: the load of the machine changes. */
#define NPS_HOST_THREADS_REPROBE 8
#endif
/** Cache line [bytes]: the words each thread writes are kept on lines of their own. */
#define NPS_HOST_THREADS_LINE 64

struct nps_host_threads {
  unsigned count, vehicles;
  unsigned min_chunk;           ///< fewest copters of a chunk (but the last)
  pthread_t *thread;            ///< count - 1 workers
  struct nps_csv_spool *spool;  ///< the log rows of each chunk of the running phase (max_chunks of them)
  unsigned max_chunks;
  nps_host_threads_fn fn;       ///< the work of the phase `generation` started
  void *ctx;                    ///< and what its copters share
  bool stopping;                ///< the next generation ends the workers
  /** chunks handed out in this phase (high 32 bits) and the first copter not handed out (low 32 bits) */
  uint64_t claimed __attribute__((aligned(NPS_HOST_THREADS_LINE)));
  unsigned generation __attribute__((aligned(NPS_HOST_THREADS_LINE)));  ///< phases started (futex word)
  unsigned workers_asleep;      ///< workers sleeping on generation
  unsigned remaining __attribute__((aligned(NPS_HOST_THREADS_LINE)));   ///< workers busy in this phase (futex word)
  unsigned main_asleep;         ///< 1 while the main thread sleeps on remaining
  /** adaptive choice between the calling thread alone (0) and every thread (1), from the measured phase times */
  struct {
    bool on;                    ///< nps_host_threads_adapt was called
    int setting;                ///< in use
    bool probing;               ///< the setting in use is on trial (NPS_HOST_THREADS_PROBE steps)
    double mean_s[2];           ///< mean step time of each setting's last window (0: not measured yet)
    unsigned age[2];            ///< windows since each setting was measured
    double window_s;            ///< step time summed in the running window
    unsigned window_phases;
    double last_phase_s;        ///< when the last phase started (CLOCK_MONOTONIC) [s]
  } adapt;
};

static void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

static void futex_wait(unsigned *word, unsigned expected)
{
  syscall(SYS_futex, word, FUTEX_WAIT_PRIVATE, expected, NULL, NULL, 0);
}

static void futex_wake_all(unsigned *word)
{
  syscall(SYS_futex, word, FUTEX_WAKE_PRIVATE, INT_MAX, NULL, NULL, 0);
}

/** Wait until *word differs from `value` (spin, then sleep counted in *asleep); returns the new value. */
static unsigned wait_for_change(unsigned *word, unsigned value, unsigned *asleep)
{
  for (int i = 0; i < NPS_HOST_THREADS_SPIN; i++) {
    const unsigned now = __atomic_load_n(word, __ATOMIC_ACQUIRE);
    if (now != value) {
      return now;
    }
    cpu_relax();
  }
  __atomic_add_fetch(asleep, 1, __ATOMIC_SEQ_CST);
  unsigned now;
  while ((now = __atomic_load_n(word, __ATOMIC_SEQ_CST)) == value) {
    futex_wait(word, value);   /* returns at once if the word changed meanwhile */
  }
  __atomic_sub_fetch(asleep, 1, __ATOMIC_SEQ_CST);
  return now;
}

/** Copters in the chunk starting at `next`: guided (see the file comment). */
static unsigned chunk_size(const struct nps_host_threads *t, unsigned next)
{
  const unsigned left = t->vehicles - next, guided = left / (2 * t->count);
  const unsigned size = guided > t->min_chunk ? guided : t->min_chunk;
  return size < left ? size : left;
}

/** Claim the next chunk: its index and copters first .. *end - 1; false when every copter is handed out. */
static bool claim_chunk(struct nps_host_threads *t, unsigned *index, unsigned *first, unsigned *end)
{
  uint64_t seen = __atomic_load_n(&t->claimed, __ATOMIC_RELAXED);
  for (;;) {
    const unsigned next = (unsigned)seen, chunk = (unsigned)(seen >> 32);
    if (next >= t->vehicles) {
      return false;
    }
    const unsigned stop = next + chunk_size(t, next);
    if (__atomic_compare_exchange_n(&t->claimed, &seen, ((uint64_t)(chunk + 1) << 32) | stop, true,
                                    __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
      *index = chunk;
      *first = next;
      *end = stop;
      return true;
    }
  }
}

/** Run chunks of the phase until none is left, each chunk's rows to its spool. */
static void run_chunks(struct nps_host_threads *t)
{
  unsigned index, first, end;
  while (claim_chunk(t, &index, &first, &end)) {
    nps_csv_spool_use(&t->spool[index]);
    for (unsigned v = first; v < end; v++) {
      t->fn(t->ctx, v);
    }
  }
  nps_csv_spool_use(NULL);
}

static void *worker_main(void *arg)
{
  struct nps_host_threads *t = arg;
  unsigned seen = 0;
  for (;;) {
    seen = wait_for_change(&t->generation, seen, &t->workers_asleep);
    if (t->stopping) {
      return NULL;
    }
    run_chunks(t);
    if (__atomic_sub_fetch(&t->remaining, 1, __ATOMIC_SEQ_CST) == 0 &&
        __atomic_load_n(&t->main_asleep, __ATOMIC_SEQ_CST) != 0) {
      futex_wake_all(&t->remaining);
    }
  }
}

/** Start the next generation: the workers run a phase, or end if t->stopping. */
static void start_generation(struct nps_host_threads *t)
{
  __atomic_store_n(&t->generation, t->generation + 1, __ATOMIC_SEQ_CST);
  if (__atomic_load_n(&t->workers_asleep, __ATOMIC_SEQ_CST) != 0) {
    futex_wake_all(&t->generation);
  }
}

unsigned nps_host_threads_default(unsigned vehicles)
{
  cpu_set_t usable;
  if (vehicles < NPS_HOST_THREADS_MIN_VEHICLES || sched_getaffinity(0, sizeof(usable), &usable) != 0) {
    return 1;
  }
  const int cores = CPU_COUNT(&usable);
  return cores < 1 ? 1 : cores > NPS_HOST_THREADS_MAX ? NPS_HOST_THREADS_MAX : (unsigned)cores;
}

/** Join the first `started` workers (after t->stopping) and free t. */
static void join_and_free(struct nps_host_threads *t, unsigned started)
{
  if (started > 1) {
    t->stopping = true;
    start_generation(t);
  }
  for (unsigned k = 1; k < started; k++) {
    pthread_join(t->thread[k - 1], NULL);
  }
  for (unsigned c = 0; t->spool != NULL && c < t->max_chunks; c++) {
    nps_csv_spool_free(&t->spool[c]);
  }
  free(t->spool);
  free(t->thread);
  free(t);
}

struct nps_host_threads *nps_host_threads_start(unsigned count, unsigned vehicles)
{
  count = count < 1 ? 1 : count > vehicles ? vehicles : count;
  struct nps_host_threads *t = NULL;
  if (posix_memalign((void **)&t, NPS_HOST_THREADS_LINE, sizeof(*t)) != 0) {
    fprintf(stderr, "error: out of memory for %u threads\n", count);
    return NULL;
  }
  memset(t, 0, sizeof(*t));
  t->count = count;
  t->vehicles = vehicles;
  const unsigned share = (vehicles + count - 1) / count;
  t->min_chunk = share < NPS_HOST_THREADS_MIN_CHUNK ? share : NPS_HOST_THREADS_MIN_CHUNK;
  /* every chunk but the last has min_chunk copters or more */
  t->max_chunks = count == 1 ? 0 : (vehicles + t->min_chunk - 1) / t->min_chunk;
  t->thread = calloc(count, sizeof(*t->thread));
  t->spool = calloc(t->max_chunks + 1, sizeof(*t->spool));
  if (t->thread == NULL || t->spool == NULL) {
    fprintf(stderr, "error: out of memory for %u threads\n", count);
    join_and_free(t, 1);
    return NULL;
  }
  for (unsigned k = 1; k < count; k++) {
    const int rc = pthread_create(&t->thread[k - 1], NULL, worker_main, t);
    if (rc != 0) {
      fprintf(stderr, "error: cannot start thread %u of %u: %s\n", k + 1, count, strerror(rc));
      join_and_free(t, k);
      return NULL;
    }
  }
  return t;
}

unsigned nps_host_threads_count(const struct nps_host_threads *t)
{
  return t->count;
}

void nps_host_threads_adapt(struct nps_host_threads *t)
{
  t->adapt.on = t->count > 1;
  t->adapt.setting = 1;
  t->adapt.probing = true;
}

static double monotonic_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/**
 * After a window of phases: keep its mean time for the setting in use, then use the faster setting, but try the
 * other one again when it has not been measured for NPS_HOST_THREADS_REPROBE windows (another process may have
 * taken a core, or left it).
 */
static void adapt_after_phase(struct nps_host_threads *t, double step_s)
{
  t->adapt.window_s += step_s;
  if (++t->adapt.window_phases < (t->adapt.probing ? NPS_HOST_THREADS_PROBE : NPS_HOST_THREADS_WINDOW)) {
    return;
  }
  const int used = t->adapt.setting, other = !used;
  t->adapt.mean_s[used] = t->adapt.window_s / t->adapt.window_phases;
  t->adapt.age[used] = 0;
  t->adapt.age[other]++;
  t->adapt.window_s = 0.0;
  t->adapt.window_phases = 0;
  t->adapt.probing = t->adapt.mean_s[other] == 0.0 || t->adapt.age[other] >= NPS_HOST_THREADS_REPROBE;
  t->adapt.setting = t->adapt.probing ? other : t->adapt.mean_s[1] < t->adapt.mean_s[0];
}

/** One phase on the calling thread alone: the rows go straight to the files, in copter order. */
static void run_alone(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx)
{
  for (unsigned v = 0; v < t->vehicles; v++) {
    fn(ctx, v);
  }
}

/** One phase on every thread (the file comment). */
static int run_together(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx);

int nps_host_threads_for_each(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx)
{
  if (t->count == 1) {
    run_alone(t, fn, ctx);
    return 0;
  }
  if (!t->adapt.on) {
    return run_together(t, fn, ctx);
  }
  /* a whole step is timed, from one phase to the next: waiting workers also slow the main thread's world step when
   * they share its core with another process */
  const double now_s = monotonic_s();
  if (t->adapt.last_phase_s > 0.0) {
    adapt_after_phase(t, now_s - t->adapt.last_phase_s);
  }
  t->adapt.last_phase_s = now_s;
  if (t->adapt.setting == 0) {
    run_alone(t, fn, ctx);
    return 0;
  }
  return run_together(t, fn, ctx);
}

unsigned nps_host_threads_in_use(const struct nps_host_threads *t)
{
  return t->adapt.on && t->adapt.setting == 0 ? 1 : t->count;
}

static int run_together(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx)
{
  t->fn = fn;
  t->ctx = ctx;
  __atomic_store_n(&t->claimed, 0, __ATOMIC_RELAXED);   /* published by start_generation */
  __atomic_store_n(&t->remaining, t->count - 1, __ATOMIC_RELAXED);
  start_generation(t);
  run_chunks(t);
  unsigned busy;
  while ((busy = __atomic_load_n(&t->remaining, __ATOMIC_ACQUIRE)) != 0) {
    wait_for_change(&t->remaining, busy, &t->main_asleep);
  }
  int rc = 0;
  const unsigned chunks = (unsigned)(__atomic_load_n(&t->claimed, __ATOMIC_RELAXED) >> 32);
  for (unsigned c = 0; c < chunks; c++) {
    if (nps_csv_spool_flush(&t->spool[c]) < 0) {
      rc = -1;
    }
  }
  return rc;
}

void nps_host_threads_stop(struct nps_host_threads *t)
{
  if (t != NULL) {
    join_and_free(t, t->count);
  }
}
