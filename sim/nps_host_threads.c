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
/** Cache line [bytes]: the words each thread writes are kept on lines of their own. */
#define NPS_HOST_THREADS_LINE 64

struct worker {
  struct nps_host_threads *pool;
  pthread_t thread;
  unsigned first, end;          ///< its copters: first .. end - 1
  struct nps_csv_spool spool;   ///< its log rows of the running phase (unused by the main thread's block)
} __attribute__((aligned(NPS_HOST_THREADS_LINE)));

struct nps_host_threads {
  unsigned count;
  struct worker *worker;        ///< count of them; worker[0] is the main thread
  nps_host_threads_fn fn;       ///< the work of the phase `generation` started
  void *ctx;                    ///< and what its copters share
  bool stopping;                ///< the next generation ends the workers
  unsigned generation __attribute__((aligned(NPS_HOST_THREADS_LINE)));  ///< phases started (futex word)
  unsigned workers_asleep;      ///< workers sleeping on generation
  unsigned remaining __attribute__((aligned(NPS_HOST_THREADS_LINE)));   ///< workers busy in this phase (futex word)
  unsigned main_asleep;         ///< 1 while the main thread sleeps on remaining
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

static void run_block(const struct worker *w, nps_host_threads_fn fn, void *ctx)
{
  for (unsigned v = w->first; v < w->end; v++) {
    fn(ctx, v);
  }
}

static void *worker_main(void *arg)
{
  struct worker *w = arg;
  struct nps_host_threads *t = w->pool;
  nps_csv_spool_use(&w->spool);
  unsigned seen = 0;
  for (;;) {
    seen = wait_for_change(&t->generation, seen, &t->workers_asleep);
    if (t->stopping) {
      return NULL;
    }
    run_block(w, t->fn, t->ctx);
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
    pthread_join(t->worker[k].thread, NULL);
  }
  for (unsigned k = 0; k < t->count; k++) {
    nps_csv_spool_free(&t->worker[k].spool);
  }
  free(t->worker);
  free(t);
}

struct nps_host_threads *nps_host_threads_start(unsigned count, unsigned vehicles)
{
  count = count < 1 ? 1 : count > vehicles ? vehicles : count;
  struct nps_host_threads *t = NULL;
  void *workers = NULL;
  if (posix_memalign((void **)&t, NPS_HOST_THREADS_LINE, sizeof(*t)) != 0 ||
      posix_memalign(&workers, NPS_HOST_THREADS_LINE, count * sizeof(struct worker)) != 0) {
    fprintf(stderr, "error: out of memory for %u threads\n", count);
    free(t);
    return NULL;
  }
  memset(t, 0, sizeof(*t));
  memset(workers, 0, count * sizeof(struct worker));
  t->count = count;
  t->worker = workers;
  for (unsigned k = 0; k < count; k++) {
    struct worker *w = &t->worker[k];
    w->pool = t;
    w->first = (unsigned)((uint64_t)vehicles * k / count);
    w->end = (unsigned)((uint64_t)vehicles * (k + 1) / count);
    const int rc = k == 0 ? 0 : pthread_create(&w->thread, NULL, worker_main, w);
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

int nps_host_threads_for_each(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx)
{
  if (t->count == 1) {
    run_block(&t->worker[0], fn, ctx);
    return 0;
  }
  t->fn = fn;
  t->ctx = ctx;
  __atomic_store_n(&t->remaining, t->count - 1, __ATOMIC_RELAXED);   /* published by start_generation */
  start_generation(t);
  run_block(&t->worker[0], fn, ctx);   /* the first block writes its rows straight to the files */
  unsigned busy;
  while ((busy = __atomic_load_n(&t->remaining, __ATOMIC_ACQUIRE)) != 0) {
    wait_for_change(&t->remaining, busy, &t->main_asleep);
  }
  int rc = 0;
  for (unsigned k = 1; k < t->count; k++) {
    if (nps_csv_spool_flush(&t->worker[k].spool) < 0) {
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
