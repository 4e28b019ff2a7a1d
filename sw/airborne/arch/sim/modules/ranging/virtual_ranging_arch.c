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
 * @file arch/sim/modules/ranging/virtual_ranging_arch.c
 * NPS variant of the ranging unit: the simulator measures every equipped peer within radio range through
 * the ranging error model and logs each reading (sw/simulator/nps/nps_swarm.h).
 */

#include "modules/ranging/virtual_ranging.h"
#include "modules/ranging/virtual_ranging_arch.h"
#include "nps_swarm.h"

static void report_peer(void *stamp_us, uint16_t peer_id, double distance_m)
{
  virtual_ranging_report(peer_id, (float)distance_m, *(const uint32_t *)stamp_us);
}

bool virtual_ranging_arch_init(void)
{
  nps_swarm_ranging_equip(VEHICLE_INDEX);
  return true;
}

void virtual_ranging_arch_periodic(uint32_t now_us)
{
  nps_swarm_ranging_measure(VEHICLE_INDEX, nps_swarm_usec_to_s(now_us), report_peer, &now_us);
}

void virtual_ranging_arch_event(uint32_t now_us)
{
  (void)now_us;   /* the simulated unit answers in the periodic call */
}
