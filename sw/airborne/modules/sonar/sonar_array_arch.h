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
 * @file modules/sonar/sonar_array_arch.h
 * What the sonar ring needs from the hardware: trigger a sonar, collect its echo. Implemented by
 * arch/linux (GPIO trigger/echo) and arch/sim (NPS: ray casts and the sensor error model).
 */

#ifndef SONAR_ARRAY_ARCH_H
#define SONAR_ARRAY_ARCH_H

#include "std.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Prepare the sonars; false if the hardware (or simulation) cannot be used. */
extern bool sonar_array_arch_init(void);
/** Send a pulse from sonar `sonar` at now_us. */
extern void sonar_array_arch_trigger(uint8_t sonar, uint32_t now_us);
/**
 * The echo of sonar `sonar`, triggered at fired_us, read at now_us: distance [m] or NAN for no echo
 * within the listening window.
 */
extern float sonar_array_arch_read(uint8_t sonar, uint32_t fired_us, uint32_t now_us);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_ARRAY_ARCH_H */
