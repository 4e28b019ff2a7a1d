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
 * @file nps_fdm_finken.c
 * First-order FINken flight model (see nps_fdm_finken.h).
 */

#include "nps_fdm_finken.h"

#include <math.h>

/** Fraction of the remaining error a first-order lag removes in dt: 1 - exp(-dt / tau). */
static double lag_gain(double dt_s, double tau_s)
{
  return tau_s > 0.0 ? 1.0 - exp(-dt_s / tau_s) : 1.0;
}

/** Angle difference wrapped to (-pi, pi]. */
static double wrap_pi(double a)
{
  return atan2(sin(a), cos(a));
}

void nps_fdm_finken_step(struct nps_fdm_finken_state *s, const struct nps_fdm_finken_params *p,
                         double vx_cmd_mps, double vy_cmd_mps, double yaw_cmd_rad, double dt_s)
{
  double speed = hypot(vx_cmd_mps, vy_cmd_mps);
  if (speed > p->max_speed_mps && speed > 0.0) {
    vx_cmd_mps *= p->max_speed_mps / speed;
    vy_cmd_mps *= p->max_speed_mps / speed;
  }
  const double gv = lag_gain(dt_s, p->velocity_tau_s);
  const double gz = lag_gain(dt_s, p->altitude_tau_s);
  const double gy = lag_gain(dt_s, p->yaw_tau_s);
  s->vel_mps[0] += (vx_cmd_mps - s->vel_mps[0]) * gv;
  s->vel_mps[1] += (vy_cmd_mps - s->vel_mps[1]) * gv;
  const double z_before = s->pos_m[2];
  s->pos_m[2] += (p->altitude_m - s->pos_m[2]) * gz;
  s->vel_mps[2] = (s->pos_m[2] - z_before) / dt_s;
  s->pos_m[0] += s->vel_mps[0] * dt_s;
  s->pos_m[1] += s->vel_mps[1] * dt_s;
  const double yaw_step = wrap_pi(yaw_cmd_rad - s->yaw_rad) * gy;
  s->yaw_rad = wrap_pi(s->yaw_rad + yaw_step);
  s->yaw_rate_rps = yaw_step / dt_s;
}
