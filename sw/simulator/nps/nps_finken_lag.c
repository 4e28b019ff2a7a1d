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
 * @file nps_finken_lag.c
 * First-order FINken flight model (see nps_finken_lag.h).
 */

#include "nps_finken_lag.h"
#include "nps_arena_contact.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/** Fraction of the remaining error a first-order lag removes in dt: 1 - exp(-dt / tau). */
static double lag_gain(double dt_s, double tau_s)
{
  return tau_s > 0.0 ? 1.0 - exp(-dt_s / tau_s) : 1.0;
}

/**
 * Angle |a| > pi wrapped to [-pi, pi]: remainder(a, 2 pi) (IEEE: a - 2 pi n with n the integer nearest a / (2 pi),
 * exact; no sin, cos, atan2 round trip), mostly without the libm call: for pi < |a| <= 4 pi, r = a -+ 2 pi is exact
 * (Sterbenz: (2 pi) / 2 <= |a| <= 2 (2 pi)); when |r| < pi, a / (2 pi) is within 1/2 of +-1, so n = +-1 and
 * remainder returns r (r = 0, at |a| = 2 pi, is left to remainder: its zero has the sign of a). 2 pi and pi are the
 * doubles remainder divides by and compares with (M_PI doubled is exact).
 */
static double wrap_pi_outside(double a)
{
  const double two_pi = 2.0 * M_PI;
  if (fabs(a) <= 2.0 * two_pi) {
    const double r = a > 0.0 ? a - two_pi : a + two_pi;
    if (r != 0.0 && fabs(r) < M_PI) {
      return r;
    }
  }
  return remainder(a, two_pi);
}

/**
 * Angle wrapped to [-pi, pi], remainder(a, 2 pi) bit for bit: an angle already in range is what remainder returns for
 * it (n = 0; at |a| = pi, a / (2 pi) = 1/2 exactly and the tie goes to the even n = 0), at the cost of a comparison.
 */
static inline double wrap_pi(double a)
{
  return fabs(a) <= M_PI ? a : wrap_pi_outside(a);
}

/** a and b are the same bits (a memo key: unlike ==, tells -0 from +0). */
static bool same_bits(double a, double b)
{
  uint64_t ua, ub;
  memcpy(&ua, &a, sizeof(ua));
  memcpy(&ub, &b, sizeof(ub));
  return ua == ub;
}

void nps_finken_lag_gains_init(struct nps_finken_lag_gains *g, const struct nps_finken_lag_params *p, double dt_s)
{
  g->dt_s = dt_s;
  g->per_step_hz = 1.0 / dt_s;
  g->velocity = lag_gain(dt_s, p->velocity_tau_s);
  g->altitude = lag_gain(dt_s, p->altitude_tau_s);
  g->yaw = lag_gain(dt_s, p->yaw_tau_s);
}

/** The horizontal velocity command scaled down to the speed limit, keeping its direction. */
static void limit_speed(struct nps_finken_lag_memo *m, const struct nps_finken_lag_params *p, double *vx_mps,
                        double *vy_mps)
{
  if (!same_bits(*vx_mps, m->vx_cmd_mps) || !same_bits(*vy_mps, m->vy_cmd_mps) ||
      !same_bits(p->max_speed_mps, m->max_speed_mps)) {
    m->max_speed_mps = p->max_speed_mps;
    m->vx_cmd_mps = m->vx_limited_mps = *vx_mps;
    m->vy_cmd_mps = m->vy_limited_mps = *vy_mps;
    /* no hypot call: speeds in m/s neither overflow nor underflow when squared */
    const double speed = sqrt(*vx_mps * *vx_mps + *vy_mps * *vy_mps);
    if (speed > p->max_speed_mps && speed > 0.0) {
      m->vx_limited_mps *= p->max_speed_mps / speed;
      m->vy_limited_mps *= p->max_speed_mps / speed;
    }
  }
  *vx_mps = m->vx_limited_mps;
  *vy_mps = m->vy_limited_mps;
}

/** Turn toward yaw_cmd_rad the short way round by the fraction gain of the wrapped error. */
static void turn(struct nps_finken_lag_state *s, double yaw_cmd_rad, double gain, double per_step_hz)
{
  const double step_rad = wrap_pi(yaw_cmd_rad - s->yaw_rad) * gain;
  s->yaw_rad = wrap_pi(s->yaw_rad + step_rad);
  s->yaw_rate_rps = step_rad * per_step_hz;
}

void nps_finken_lag_advance(struct nps_finken_lag_state *s, const struct nps_finken_lag_params *p,
                            const struct nps_finken_lag_gains *g, double vx_cmd_mps, double vy_cmd_mps,
                            double yaw_cmd_rad)
{
  const double dt_s = g->dt_s;
  limit_speed(&s->memo, p, &vx_cmd_mps, &vy_cmd_mps);
  s->vel_mps[0] += (vx_cmd_mps - s->vel_mps[0]) * g->velocity;
  s->vel_mps[1] += (vy_cmd_mps - s->vel_mps[1]) * g->velocity;
  const double z_before = s->pos_m[2];
  s->pos_m[2] += (p->altitude_m - s->pos_m[2]) * g->altitude;
  s->vel_mps[2] = (s->pos_m[2] - z_before) * g->per_step_hz;
  s->pos_m[0] += s->vel_mps[0] * dt_s;
  s->pos_m[1] += s->vel_mps[1] * dt_s;
  turn(s, yaw_cmd_rad, g->yaw, g->per_step_hz);
}

void nps_finken_lag_step(struct nps_finken_lag_state *s, const struct nps_finken_lag_params *p,
                         double vx_cmd_mps, double vy_cmd_mps, double yaw_cmd_rad, double dt_s)
{
  struct nps_finken_lag_gains g;
  nps_finken_lag_gains_init(&g, p, dt_s);
  nps_finken_lag_advance(s, p, &g, vx_cmd_mps, vy_cmd_mps, yaw_cmd_rad);
}

void nps_finken_lag_take_contact(struct nps_finken_lag_state *s, const double pos_m[2])
{
  nps_arena_contact_take(s->pos_m, s->vel_mps, pos_m);
}
