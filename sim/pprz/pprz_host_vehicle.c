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
 * @file pprz_host_vehicle.c
 * Per-vehicle slots of the multi-vehicle host (see pprz_host_vehicle.h).
 */

#include "pprz_host_vehicle.h"

#include <stdio.h>
#include <stdlib.h>

/** Most per-vehicle variables one host binary holds (a few per module). */
#define PPRZ_VEHICLE_MAX_SLOTS 256

__thread unsigned pprz_vehicle_index;
unsigned pprz_vehicle_count;
static uint16_t *vehicle_ac_ids;
/** The registered variables (pprz_vehicle_slots_register): given their slots by every set-up, freed by teardown. */
static struct registered_slots {
  void **slots;
  size_t size;
} registered[PPRZ_VEHICLE_MAX_SLOTS];
static unsigned registered_count;

void pprz_vehicle_fatal(const char *what)
{
  fprintf(stderr, "pprz host: %s\n", what);
  abort();
}

void pprz_vehicles_teardown(void)
{
  for (unsigned i = 0; i < registered_count; i++) {
    free(*registered[i].slots);
    *registered[i].slots = NULL;
  }
  free(vehicle_ac_ids);
  vehicle_ac_ids = NULL;
  pprz_vehicle_count = 0;
  pprz_vehicle_index = 0;
}

void pprz_vehicles_setup(unsigned count, const uint16_t *ac_ids)
{
  pprz_vehicles_teardown();
  if (count == 0) {
    pprz_vehicle_fatal("at least one vehicle is needed");
  }
  vehicle_ac_ids = malloc(count * sizeof(*vehicle_ac_ids));
  if (vehicle_ac_ids == NULL) {
    pprz_vehicle_fatal("out of memory for the vehicle table");
  }
  for (unsigned i = 0; i < count; i++) {
    vehicle_ac_ids[i] = ac_ids ? ac_ids[i] : (uint16_t)(i + 1);
  }
  pprz_vehicle_count = count;
  for (unsigned i = 0; i < registered_count; i++) {   /* one zeroed slot per vehicle for every registered variable */
    *registered[i].slots = calloc(count, registered[i].size);
    if (*registered[i].slots == NULL) {
      pprz_vehicle_fatal("out of memory for per-vehicle state");
    }
  }
}

void pprz_vehicle_slots_register(void **slots, size_t size)
{
  if (registered_count == PPRZ_VEHICLE_MAX_SLOTS) {
    pprz_vehicle_fatal("too many per-vehicle variables (raise PPRZ_VEHICLE_MAX_SLOTS)");
  }
  registered[registered_count++] = (struct registered_slots) { slots, size };
}

void pprz_vehicle_select(unsigned index)
{
  if (index >= pprz_vehicle_count) {
    pprz_vehicle_fatal("vehicle index out of range");
  }
  pprz_vehicle_index = index;
}

uint16_t pprz_vehicle_ac_id(void)
{
  return vehicle_ac_ids ? vehicle_ac_ids[pprz_vehicle_index] : 1;
}

