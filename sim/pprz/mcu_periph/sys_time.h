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
 * @file mcu_periph/sys_time.h
 * Host stand-in for Paparazzi's sys_time: the simulated clock, shared by all vehicles (they run in lock step).
 */

#ifndef SYS_TIME_H
#define SYS_TIME_H

#include "std.h"

/** Host clock resolution: one CPU tick is one microsecond (a constant, as a Paparazzi arch's tick rate is). */
#define HOST_CPU_TICKS_PER_SEC 1000000

/** CPU ticks to microseconds (Paparazzi's arch macro; the factor folds to 1 at compile time). */
#define usec_of_cpu_ticks(t) ((t) * (1000000 / HOST_CPU_TICKS_PER_SEC))

struct sys_time {
  uint32_t nb_sec;            ///< full seconds since startup
  uint32_t nb_sec_rem;        ///< remainder of seconds since startup in CPU ticks
  uint32_t nb_tick;           ///< SYS_TIME_TICKS since startup
  float resolution;           ///< tick duration [s]
  uint32_t ticks_per_sec;     ///< SYS_TIME_TICKS per second
  uint32_t cpu_ticks_per_sec; ///< CPU ticks per second (HOST_CPU_TICKS_PER_SEC)
};

extern struct sys_time sys_time;

/** Host only: set the simulated time [s]. */
extern void sys_time_host_set(double time_s);

static inline float get_sys_time_float(void)
{
  return (float)(sys_time.nb_sec + (float)(sys_time.nb_sec_rem) / sys_time.cpu_ticks_per_sec);
}

static inline uint32_t get_sys_time_usec(void)
{
  return sys_time.nb_sec * 1000000 + usec_of_cpu_ticks(sys_time.nb_sec_rem);
}

static inline uint32_t get_sys_time_msec(void)
{
  return get_sys_time_usec() / 1000;
}

#endif /* SYS_TIME_H */
