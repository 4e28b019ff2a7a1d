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
 * @file pprz_host_vehicle.h
 * The host's vehicle context: which of the N simulated copters the module code runs for now.
 *
 * The host may run the copters' modules on several threads (nps_host_threads.h): the current vehicle is
 * per thread. Every per-vehicle variable is registered (pprz_vehicle_slots_register) and gets its slots at set-up,
 * before any thread starts.
 */

#ifndef PPRZ_HOST_VEHICLE_H
#define PPRZ_HOST_VEHICLE_H

#include <stddef.h>
#include <stdint.h>

/** Index (0..count-1) of the vehicle whose modules run now on this thread; set by pprz_vehicle_select. */
extern __thread unsigned pprz_vehicle_index;
/** Number of simulated vehicles. */
extern unsigned pprz_vehicle_count;

/** Declare `count` vehicles with the given aircraft ids; frees every per-vehicle slot of a previous set-up. */
extern void pprz_vehicles_setup(unsigned count, const uint16_t *ac_ids);
/** Release every per-vehicle slot (end of a run or of a test). */
extern void pprz_vehicles_teardown(void);
/** Make vehicle `index` the current one of this thread (its ABI queues, module state, flight model). */
extern void pprz_vehicle_select(unsigned index);
/** Aircraft id of the current vehicle (what AC_ID is on a real copter; 16 bit so a simulated swarm may exceed 255). */
extern uint16_t pprz_vehicle_ac_id(void);
/**
 * Register a per-vehicle variable before pprz_vehicles_setup (VEHICLE_LOCAL_DEFINE does it before main): each
 * set-up gives it one zeroed `size`-byte slot per vehicle behind `*slots` at once, so that reaching the current
 * vehicle's slot is a plain index (VEHICLE_LOCAL), with no check on the way.
 */
extern void pprz_vehicle_slots_register(void **slots, size_t size);
/** Print `what` and abort (a misused vehicle context, e.g. a per-vehicle variable used where it has no slot). */
extern void pprz_vehicle_fatal(const char *what) __attribute__((noreturn));

/**
 * The check of a registered variable's access in a checked build (VEHICLE_LOCAL, vehicle_local.h): its slots exist
 * (between pprz_vehicles_setup and pprz_vehicles_teardown) and the current vehicle is one of them.
 */
static inline void pprz_vehicle_check_slots(const void *slots)
{
  if (slots == NULL) {
    pprz_vehicle_fatal("per-vehicle state used before pprz_vehicles_setup() (or after pprz_vehicles_teardown())");
  }
  if (pprz_vehicle_index >= pprz_vehicle_count) {
    pprz_vehicle_fatal("per-vehicle state used with no vehicle selected in range");
  }
}

#endif /* PPRZ_HOST_VEHICLE_H */
