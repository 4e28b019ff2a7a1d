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
 * @file host_stand_ins.c
 * Storage behind the host's stand-ins for Paparazzi's ABI queues, state, sys_time, NpsFdm (with fdm_finken's
 * placement) and guided mode.
 */

#include "modules/core/abi.h"
#include "state.h"
#include "mcu_periph/sys_time.h"
#include "nps_fdm.h"
#include "nps_fdm_finken.h"
#include "firmwares/rotorcraft/autopilot_guided.h"
#include "pprz_host_vehicle.h"

#include <math.h>

struct sys_time sys_time = {
  .resolution = 1.0f / HOST_CPU_TICKS_PER_SEC,
  .ticks_per_sec = HOST_CPU_TICKS_PER_SEC,
  .cpu_ticks_per_sec = HOST_CPU_TICKS_PER_SEC,
};

void sys_time_host_set(double time_s)
{
  /* the time rounded to ticks once; the full seconds and the ticks left follow from it exactly */
  const uint64_t ticks = (uint64_t)llround(time_s * HOST_CPU_TICKS_PER_SEC);
  sys_time.nb_sec = (uint32_t)(ticks / HOST_CPU_TICKS_PER_SEC);
  sys_time.nb_sec_rem = (uint32_t)(ticks % HOST_CPU_TICKS_PER_SEC);
  sys_time.nb_tick = (uint32_t)ticks;
}

static abi_event **abi_queues_per_vehicle;   ///< ABI_MESSAGE_NB queue heads per vehicle
static struct State *state_per_vehicle;
static struct NpsFdm *fdm_per_vehicle;
static struct autopilot_guided_command *guided_per_vehicle;
static nps_fdm_source_fn fdm_source;   ///< set by the host before its threads start

/** The stand-ins' per-vehicle variables get their slots from pprz_vehicles_setup (registered before main). */
static void __attribute__((constructor)) register_stand_ins(void)
{
  pprz_vehicle_slots_register((void **)&abi_queues_per_vehicle, ABI_MESSAGE_NB * sizeof(abi_event *));
  pprz_vehicle_slots_register((void **)&state_per_vehicle, sizeof(struct State));
  pprz_vehicle_slots_register((void **)&fdm_per_vehicle, sizeof(struct NpsFdm));
  pprz_vehicle_slots_register((void **)&guided_per_vehicle, sizeof(struct autopilot_guided_command));
}

abi_event **abi_queues_current(void)
{
  return abi_queues_per_vehicle + (size_t)pprz_vehicle_index * ABI_MESSAGE_NB;
}

struct State *state_current(void)
{
  return state_per_vehicle + pprz_vehicle_index;
}

void nps_fdm_set_source(nps_fdm_source_fn source)
{
  fdm_source = source;
}

struct NpsFdm *nps_fdm_current(void)
{
  struct NpsFdm *f = fdm_per_vehicle + pprz_vehicle_index;
  if (fdm_source != NULL) {
    fdm_source(f, pprz_vehicle_index);
  }
  return f;
}

/** fdm_finken's placement, for the host's stand-in fdm: at rest on the ground there (a source, when set, overrides). */
void nps_fdm_finken_place(double north_m, double east_m, double heading_rad)
{
  struct NpsFdm *f = fdm_per_vehicle + pprz_vehicle_index;
  f->ltpprz_pos = (struct NedCoor_d) { north_m, east_m, 0.0 };
  f->ltpprz_ecef_vel = (struct NedCoor_d) { 0.0, 0.0, 0.0 };
  f->ltpprz_to_body_eulers = (struct DoubleEulers) { 0.0, 0.0, heading_rad };
  f->ltpprz_to_body_quat = (struct DoubleQuat) { cos(0.5 * heading_rad), 0.0, 0.0, sin(0.5 * heading_rad) };
  f->agl = 0.0;
  f->on_ground = true;
}

/** fdm_finken's contact, for the host's stand-in fdm: the position moved there (a source, when set, overrides). */
void nps_fdm_finken_take_contact(double north_m, double east_m)
{
  struct NpsFdm *f = fdm_per_vehicle + pprz_vehicle_index;
  f->ltpprz_pos.x = north_m;
  f->ltpprz_pos.y = east_m;
}

struct autopilot_guided_command *autopilot_guided_current(void)
{
  return guided_per_vehicle + pprz_vehicle_index;
}

bool autopilot_guided_move_ned(float vx, float vy, float vz, float heading)
{
  struct autopilot_guided_command *cmd = autopilot_guided_current();
  cmd->vx = vx;
  cmd->vy = vy;
  cmd->vz = vz;
  cmd->heading = heading;
  cmd->active = true;
  return true;
}
