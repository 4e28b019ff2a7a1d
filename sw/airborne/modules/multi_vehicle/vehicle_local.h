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
 * @file modules/multi_vehicle/vehicle_local.h
 * Module state that is one variable on a copter and one per copter in the multi-vehicle NPS host.
 *
 * A Paparazzi module keeps its state in globals. To let one host process simulate N copters, our
 * modules declare that state with these macros and reach it through VEHICLE_LOCAL(name):
 *
 *     VEHICLE_LOCAL_DEFINE(struct sonar_array, sonar_array);      // in the .c file
 *     struct sonar_array *sa = VEHICLE_LOCAL(sonar_array);        // in any function
 *
 * In a Paparazzi build this is a plain global `struct sonar_array sonar_array;` (so settings and
 * telemetry can name it); with PPRZ_HOST_MULTI_VEHICLE (the host in sim/) it is one slot per vehicle,
 * the slot of the vehicle the host is running now (every vehicle's slots exist from pprz_vehicles_setup on: use
 * VEHICLE_LOCAL only after it). An access is a plain index with no check; a build with AddressSanitizer (the
 * test builds) or -DPPRZ_VEHICLE_CHECKS checks every access and stops with a message on a use before
 * pprz_vehicles_setup or after pprz_vehicles_teardown. VEHICLE_INDEX is that vehicle's index (0 .. n-1),
 * for the NPS variants that ask the simulator about "this copter"; 0 in a Paparazzi build.
 */

#ifndef VEHICLE_LOCAL_H
#define VEHICLE_LOCAL_H

#ifdef PPRZ_HOST_MULTI_VEHICLE
#include "pprz_host_vehicle.h"
#endif

#ifdef __cplusplus
extern "C" {
#endif

#ifdef PPRZ_HOST_MULTI_VEHICLE
#define VEHICLE_LOCAL_DECLARE(type, name) extern type *name##_per_vehicle
/* the slots are registered before main (a constructor), and allocated by pprz_vehicles_setup */
#define VEHICLE_LOCAL_DEFINE(type, name) \
  extern type *name##_per_vehicle; \
  static void __attribute__((constructor)) name##_per_vehicle_register(void) \
  { \
    pprz_vehicle_slots_register((void **)&name##_per_vehicle, sizeof(type)); \
  } \
  type *name##_per_vehicle
#if defined(PPRZ_VEHICLE_CHECKS) || defined(__SANITIZE_ADDRESS__)
#define VEHICLE_LOCAL(name) (pprz_vehicle_check_slots(name##_per_vehicle), name##_per_vehicle + pprz_vehicle_index)
#else
#define VEHICLE_LOCAL(name) (name##_per_vehicle + pprz_vehicle_index)
#endif
#define VEHICLE_INDEX (pprz_vehicle_index)
#else
#define VEHICLE_LOCAL_DECLARE(type, name) extern type name
#define VEHICLE_LOCAL_DEFINE(type, name) type name
#define VEHICLE_LOCAL(name) (&(name))
#define VEHICLE_INDEX 0u
#endif

#ifdef __cplusplus
}
#endif

#endif /* VEHICLE_LOCAL_H */
