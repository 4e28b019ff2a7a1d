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
 * @file arch/sim/modules/sonar/sonar_array_arch.c
 * NPS variant of the sonar ring: the simulator casts the ray, adds cross-talk from other copters' pulses
 * and the sonar error model, and logs the reading (sw/simulator/nps/nps_swarm.h).
 */

#include "modules/sonar/sonar_array.h"
#include "modules/sonar/sonar_array_arch.h"
#include "modules/sonar/sonar_array_nps_noise.h"
#include "nps_swarm.h"

bool sonar_array_arch_init(void)
{
  nps_swarm_sonar_attach(VEHICLE_INDEX, 1.0 / SONAR_ARRAY_RATE);
  sonar_array_nps_noise_init();
  return true;
}

void sonar_array_arch_trigger(uint8_t sonar, uint32_t now_us)
{
  nps_swarm_sonar_trigger(VEHICLE_INDEX, sonar, nps_swarm_usec_to_s(now_us));
}

float sonar_array_arch_read(uint8_t sonar, uint32_t fired_us, uint32_t now_us)
{
  sonar_array_nps_noise_apply();
  return (float)nps_swarm_sonar_read(VEHICLE_INDEX, sonar, nps_swarm_usec_to_s(fired_us), nps_swarm_usec_to_s(now_us));
}
