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
 * @file arch/linux/modules/sonar/sonar_gpio_temperature.h
 * The air temperature the sonars use for the speed of sound: SONAR_GPIO_TEMPERATURE until Paparazzi's
 * TEMPERATURE ABI message brings a measurement (from SONAR_GPIO_TEMPERATURE_SENDER_ID, any sender by default).
 * Messages outside [SONAR_ECHO_TEMP_MIN_C, SONAR_ECHO_TEMP_MAX_C] (or NAN) are a sensor fault: ignored and
 * counted. One value per copter (VEHICLE_LOCAL).
 */

#ifndef SONAR_GPIO_TEMPERATURE_H
#define SONAR_GPIO_TEMPERATURE_H

#include "std.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Air temperature until a TEMPERATURE message arrives [deg C] (airframe define) */
#ifndef SONAR_GPIO_TEMPERATURE
#define SONAR_GPIO_TEMPERATURE 20.0f
#endif
/** Sender of the TEMPERATURE messages to use (ABI_BROADCAST: any) */
#ifndef SONAR_GPIO_TEMPERATURE_SENDER_ID
#define SONAR_GPIO_TEMPERATURE_SENDER_ID ABI_BROADCAST
#endif

/**
 * Start from SONAR_GPIO_TEMPERATURE and bind the TEMPERATURE message (once per copter).
 * @return false if SONAR_GPIO_TEMPERATURE is outside [SONAR_ECHO_TEMP_MIN_C, SONAR_ECHO_TEMP_MAX_C]
 */
extern bool sonar_gpio_temperature_init(void);

/** The air temperature to use now [deg C]. */
extern float sonar_gpio_temperature_c(void);

/** TEMPERATURE messages ignored as out of range. */
extern uint32_t sonar_gpio_temperature_rejected(void);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_GPIO_TEMPERATURE_H */
