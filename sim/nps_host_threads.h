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
 * @file nps_host_threads.h
 * The per-copter work of a host step on several threads, with logs that do not depend on the thread count.
 *
 * A step is the simulator's world step (grid, contacts, walls) on the main thread, then one phase over the
 * copters (each copter's state to its modules, its modules, its flight model: nps_host_world.h). In a phase,
 * the threads (the calling, main, thread among them) take chunks of consecutive copters in
 * copter order as they get free, and run a chunk's copters in copter order; each chunk's log rows go to a
 * spool of its own (nps_csv_spool) and the main thread appends the spools in chunk order once every thread
 * is done: the rows come out in the order of a single-threaded run. A copter's work may read every copter's simulator
 * state but writes only its own copter's; the shared state it does write is made thread-safe (per-thread
 * current vehicle, per-vehicle slots allocated under a lock, sonar pulses published between steps).
 */

#ifndef NPS_HOST_THREADS_H
#define NPS_HOST_THREADS_H

#include <stdint.h>

/** Below this many copters the default is one thread: a step is too short to pay for the synchronisation (on the
 * 2-core development machine a second thread makes 4 copters 1.9 x slower, 8 copters 1.2 x slower, 12 copters as
 * fast and 16 copters 1.11 x faster: docs/host.md#threads). */
#define NPS_HOST_THREADS_MIN_VEHICLES 16
/** Most threads --threads accepts. */
#define NPS_HOST_THREADS_MAX 64

/** The work of copter v in a phase (it selects the vehicle itself); ctx: what the phase's copters share. */
typedef void (*nps_host_threads_fn)(void *ctx, unsigned v);

struct nps_host_threads;

/** Default thread count: the usable cores (sched_getaffinity), 1 below NPS_HOST_THREADS_MIN_VEHICLES copters. */
extern unsigned nps_host_threads_default(unsigned vehicles);
/** Start min(count, vehicles) - 1 worker threads (the caller is the first); NULL with a message on stderr. */
extern struct nps_host_threads *nps_host_threads_start(unsigned count, unsigned vehicles);
/** Threads in use (the caller included). */
extern unsigned nps_host_threads_count(const struct nps_host_threads *t);
/** One phase: fn(ctx, v) for every copter, then the spooled log rows appended in copter order; -1 if rows were lost. */
extern int nps_host_threads_for_each(struct nps_host_threads *t, nps_host_threads_fn fn, void *ctx);
/**
 * Choose from measurements, for every later phase, between the calling thread alone and every thread: the faster
 * of the two over the last window of phases, the other one tried again now and then. For a default thread count:
 * on a machine where other processes keep cores busy, threads that wait for each other are slower than one
 * (docs/host.md#threads). The logs are the same either way.
 */
extern void nps_host_threads_adapt(struct nps_host_threads *t);
/** Threads the last phase ran on (1 while the adaptive choice runs the calling thread alone). */
extern unsigned nps_host_threads_in_use(const struct nps_host_threads *t);
/** Join the workers and free everything (NULL is fine). */
extern void nps_host_threads_stop(struct nps_host_threads *t);

#endif /* NPS_HOST_THREADS_H */
