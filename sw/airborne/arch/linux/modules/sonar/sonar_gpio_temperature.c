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
 * @file arch/linux/modules/sonar/sonar_gpio_temperature.c
 * Air temperature for the sonars from an airframe define or the TEMPERATURE ABI message.
 */

#include "modules/sonar/sonar_gpio_temperature.h"
#include "modules/sonar/sonar_echo.h"
#include "modules/core/abi.h"
#include "modules/multi_vehicle/vehicle_local.h"

struct sonar_gpio_temperature {
  abi_event ev;
  float temperature_c;
  uint32_t rejected;
};

VEHICLE_LOCAL_DEFINE(struct sonar_gpio_temperature, sonar_gpio_temperature);

static void temperature_cb(uint8_t sender_id __attribute__((unused)), float temp)
{
  struct sonar_gpio_temperature *t = VEHICLE_LOCAL(sonar_gpio_temperature);
  if (temp >= SONAR_ECHO_TEMP_MIN_C && temp <= SONAR_ECHO_TEMP_MAX_C) {
    t->temperature_c = temp;
  } else {
    t->rejected++;
  }
}

bool sonar_gpio_temperature_init(void)
{
  struct sonar_gpio_temperature *t = VEHICLE_LOCAL(sonar_gpio_temperature);
  const float initial_c = SONAR_GPIO_TEMPERATURE;
  if (!(initial_c >= SONAR_ECHO_TEMP_MIN_C && initial_c <= SONAR_ECHO_TEMP_MAX_C)) {
    return false;
  }
  t->temperature_c = initial_c;
  t->rejected = 0;
  AbiBindMsgTEMPERATURE(SONAR_GPIO_TEMPERATURE_SENDER_ID, &t->ev, temperature_cb);
  return true;
}

float sonar_gpio_temperature_c(void)
{
  return VEHICLE_LOCAL(sonar_gpio_temperature)->temperature_c;
}

uint32_t sonar_gpio_temperature_rejected(void)
{
  return VEHICLE_LOCAL(sonar_gpio_temperature)->rejected;
}
