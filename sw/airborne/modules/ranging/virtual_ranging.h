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
 * @file modules/ranging/virtual_ranging.h
 * Radio ranging between FINken: the distance to every other copter that carries a ranging unit,
 * omnidirectional (no direction), not occluded, 0 to VIRTUAL_RANGING_MAX_RANGE (report, section 4.1).
 *
 * Each distance is published on ABI as RANGING_DISTANCE (peer aircraft id, distance [m], stamp [us]) and kept
 * in a per-peer table (ranging_table.h) that other modules read with virtual_ranging_table(). The hardware (a
 * ranging unit on CAN) or its NPS simulation sits behind virtual_ranging_arch.h.
 */

#ifndef VIRTUAL_RANGING_H
#define VIRTUAL_RANGING_H

#include "std.h"
#include "modules/ranging/ranging_table.h"
#include "modules/multi_vehicle/vehicle_local.h"

#ifdef __cplusplus
extern "C" {
#endif

/** ABI sender id of RANGING_DISTANCE */
#ifndef VIRTUAL_RANGING_ID
#define VIRTUAL_RANGING_ID 220
#endif
/** Longest distance measured [m]; farther peers read as this (report, section 4.2) */
#ifndef VIRTUAL_RANGING_MAX_RANGE
#define VIRTUAL_RANGING_MAX_RANGE 2.5f
#endif
/** A peer's distance older than this is no longer fresh [s] */
#ifndef VIRTUAL_RANGING_STALE_TIME
#define VIRTUAL_RANGING_STALE_TIME 0.5f
#endif

struct virtual_ranging {
  struct ranging_table table;
  bool running;   ///< false if the ranging unit could not be opened
};

VEHICLE_LOCAL_DECLARE(struct virtual_ranging, virtual_ranging);

/** The per-peer table of the current copter. */
extern const struct ranging_table *virtual_ranging_table(void);

/** Called by the arch layer for each distance received: clamps to [0, max], stores, publishes. */
extern void virtual_ranging_report(uint16_t peer_id, float distance_m, uint32_t stamp_us);

extern void virtual_ranging_init(void);
extern void virtual_ranging_periodic(void);
extern void virtual_ranging_event(void);

#ifdef __cplusplus
}
#endif

#endif /* VIRTUAL_RANGING_H */
