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
 * @file nps_finken_quadrotor.c
 * Rigid-body FINken quadrotor (see nps_finken_quadrotor.h).
 */

#include "nps_finken_quadrotor.h"

#include <math.h>
#include <string.h>

#define ROTORS NPS_FINKEN_QUADROTOR_ROTORS

/** The integrated part of the state: position, velocity (NED), attitude quaternion, body rates. */
struct body {
  double pos[3], vel[3], quat[4], rates[3];
};

/* add_scaled walks a struct body as one array of doubles */
_Static_assert(sizeof(struct body) == 13 * sizeof(double), "struct body is 13 doubles without padding");

/** What is held over one Runge-Kutta step. */
struct inputs {
  double thrust_n;                   ///< total thrust along -z body [N]
  double torque_nm[3];               ///< rotor torques about the body axes [N m]
  double wind[3];                    ///< NED [m/s]
};

/** M v with M the rotation ltp -> body of the unit quaternion q (Paparazzi's rmat_of_quat). */
static void body_of_ltp(const double q[4], const double v[3], double out[3])
{
  const double qi = q[0], qx = q[1], qy = q[2], qz = q[3];
  const double m[3][3] = {
    { 1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qi * qz), 2 * (qx * qz - qi * qy) },
    { 2 * (qx * qy - qi * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qi * qx) },
    { 2 * (qx * qz + qi * qy), 2 * (qy * qz - qi * qx), 1 - 2 * (qx * qx + qy * qy) },
  };
  for (int i = 0; i < 3; i++) {
    out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  }
}

/** M^T v: a body vector in the ltp frame. */
static void ltp_of_body(const double q[4], const double v[3], double out[3])
{
  const double conj[4] = { q[0], -q[1], -q[2], -q[3] };
  body_of_ltp(conj, v, out);
}

/** Specific force (thrust and drag over the mass) in the body frame. */
static void specific_force(const struct body *b, const struct nps_finken_quadrotor_params *p, const struct inputs *in,
                           double f_body[3])
{
  const double air_ltp[3] = { b->vel[0] - in->wind[0], b->vel[1] - in->wind[1], b->vel[2] - in->wind[2] };
  double air_body[3];
  body_of_ltp(b->quat, air_ltp, air_body);
  for (int i = 0; i < 3; i++) {
    f_body[i] = -p->drag_ns_m[i] * air_body[i] / p->mass_kg;
  }
  f_body[2] -= in->thrust_n / p->mass_kg;
}

/** Time derivative of the body state (d: the same layout, each member its derivative); the acceleration in NED. */
static void derivative(const struct body *b, const struct nps_finken_quadrotor_params *p, const struct inputs *in,
                       struct body *d)
{
  double f_body[3], f_ltp[3];
  specific_force(b, p, in, f_body);
  ltp_of_body(b->quat, f_body, f_ltp);
  for (int i = 0; i < 3; i++) {
    d->pos[i] = b->vel[i];
    d->vel[i] = f_ltp[i];
  }
  d->vel[2] += p->gravity_mps2;

  const double *w = b->rates, *I = p->inertia_kgm2;
  const double Iw[3] = { I[0] * w[0], I[1] * w[1], I[2] * w[2] };
  const double gyro[3] = { w[1] * Iw[2] - w[2] * Iw[1], w[2] * Iw[0] - w[0] * Iw[2], w[0] * Iw[1] - w[1] * Iw[0] };
  for (int i = 0; i < 3; i++) {
    d->rates[i] = (in->torque_nm[i] - gyro[i]) / I[i];
  }

  const double *q = b->quat;
  d->quat[0] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2]);
  d->quat[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
  d->quat[2] = 0.5 * (q[0] * w[1] - q[1] * w[2] + q[3] * w[0]);
  d->quat[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
}

/** out = b + h d, member by member. */
static void add_scaled(const struct body *b, double h, const struct body *d, struct body *out)
{
  const double *x = (const double *)b, *dx = (const double *)d;
  double *o = (double *)out;
  for (size_t i = 0; i < sizeof(struct body) / sizeof(double); i++) {
    o[i] = x[i] + h * dx[i];
  }
}

static void normalise_quat(double q[4])
{
  const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int i = 0; i < 4; i++) {
    q[i] /= n;
  }
}

void nps_finken_quadrotor_set_rotors(struct nps_finken_quadrotor_params *p, const double *roll_coef,
                                     const double *pitch_coef, const double *yaw_coef, double arm_m)
{
  for (int i = 0; i < ROTORS; i++) {
    const double x = pitch_coef[i], y = -roll_coef[i], n = hypot(x, y);
    p->rotor_pos_m[i][0] = n > 0.0 ? arm_m * x / n : 0.0;
    p->rotor_pos_m[i][1] = n > 0.0 ? arm_m * y / n : 0.0;
    p->rotor_spin[i] = yaw_coef[i] > 0.0 ? 1.0 : yaw_coef[i] < 0.0 ? -1.0 : 0.0;
  }
}

void nps_finken_quadrotor_init(struct nps_finken_quadrotor_state *s, double north_m, double east_m, double psi_rad)
{
  memset(s, 0, sizeof(*s));
  s->pos_m[0] = north_m;
  s->pos_m[1] = east_m;
  s->quat[0] = cos(psi_rad / 2.0);
  s->quat[3] = sin(psi_rad / 2.0);
  s->on_ground = true;
}

double nps_finken_quadrotor_hover_command(const struct nps_finken_quadrotor_params *p)
{
  return sqrt(p->mass_kg * p->gravity_mps2 / (ROTORS * p->max_thrust_n));
}

/** Thrust and torques of the rotors at their speeds. */
static void rotor_forces(const struct nps_finken_quadrotor_state *s, const struct nps_finken_quadrotor_params *p,
                         struct inputs *in)
{
  in->thrust_n = 0.0;
  in->torque_nm[0] = in->torque_nm[1] = in->torque_nm[2] = 0.0;
  for (int i = 0; i < ROTORS; i++) {
    const double t = p->max_thrust_n * s->rotor_speed[i] * s->rotor_speed[i];
    in->thrust_n += t;
    /* r x F with r = (x, y, 0), F = (0, 0, -t) */
    in->torque_nm[0] += -p->rotor_pos_m[i][1] * t;
    in->torque_nm[1] += p->rotor_pos_m[i][0] * t;
    in->torque_nm[2] += p->rotor_spin[i] * p->torque_coef_m * t;
  }
}

/** Flat on the ground at z = 0, heading kept, at rest. */
static void land(struct body *b)
{
  const double *q = b->quat;
  const double psi = atan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] * q[2] + q[3] * q[3]));
  b->quat[0] = cos(psi / 2.0);
  b->quat[1] = b->quat[2] = 0.0;
  b->quat[3] = sin(psi / 2.0);
  b->pos[2] = 0.0;
  for (int i = 0; i < 3; i++) {
    b->vel[i] = 0.0;
    b->rates[i] = 0.0;
  }
}

void nps_finken_quadrotor_step(struct nps_finken_quadrotor_state *s, const struct nps_finken_quadrotor_params *p,
                               const double commands[NPS_FINKEN_QUADROTOR_ROTORS], const double *wind_ned_mps,
                               double dt_s)
{
  if (!(dt_s > 0.0)) {
    return;
  }
  const double lag = p->rotor_tau_s > 0.0 ? 1.0 - exp(-dt_s / p->rotor_tau_s) : 1.0;
  for (int i = 0; i < ROTORS; i++) {
    const double c = fmin(fmax(commands[i], 0.0), 1.0);   /* fmax(NaN, 0) = 0 */
    s->rotor_speed[i] += (c - s->rotor_speed[i]) * lag;
  }
  struct inputs in;
  rotor_forces(s, p, &in);
  for (int i = 0; i < 3; i++) {
    in.wind[i] = wind_ned_mps ? wind_ned_mps[i] : 0.0;
  }

  struct body b, k1, k2, k3, k4, tmp;
  memcpy(b.pos, s->pos_m, sizeof(b.pos));
  memcpy(b.vel, s->vel_mps, sizeof(b.vel));
  memcpy(b.quat, s->quat, sizeof(b.quat));
  memcpy(b.rates, s->rates_rps, sizeof(b.rates));
  derivative(&b, p, &in, &k1);
  add_scaled(&b, dt_s / 2.0, &k1, &tmp);
  derivative(&tmp, p, &in, &k2);
  add_scaled(&b, dt_s / 2.0, &k2, &tmp);
  derivative(&tmp, p, &in, &k3);
  add_scaled(&b, dt_s, &k3, &tmp);
  derivative(&tmp, p, &in, &k4);
  add_scaled(&b, dt_s / 6.0, &k1, &b);
  add_scaled(&b, dt_s / 3.0, &k2, &b);
  add_scaled(&b, dt_s / 3.0, &k3, &b);
  add_scaled(&b, dt_s / 6.0, &k4, &b);
  normalise_quat(b.quat);

  s->on_ground = b.pos[2] > 0.0;
  if (s->on_ground) {
    land(&b);
  }
  memcpy(s->pos_m, b.pos, sizeof(b.pos));
  memcpy(s->vel_mps, b.vel, sizeof(b.vel));
  memcpy(s->quat, b.quat, sizeof(b.quat));
  memcpy(s->rates_rps, b.rates, sizeof(b.rates));

  /* outputs at the end of the step */
  struct body d;
  derivative(&b, p, &in, &d);
  s->thrust_n = in.thrust_n;
  if (s->on_ground) {
    /* held by the ground: no acceleration, the accelerometer reads the ground's push, -g along the vertical */
    const double up[3] = { 0.0, 0.0, -p->gravity_mps2 };
    memset(s->accel_mps2, 0, sizeof(s->accel_mps2));
    memset(s->rot_accel_rps2, 0, sizeof(s->rot_accel_rps2));
    body_of_ltp(b.quat, up, s->specific_force_mps2);
  } else {
    memcpy(s->accel_mps2, d.vel, sizeof(d.vel));
    memcpy(s->rot_accel_rps2, d.rates, sizeof(d.rates));
    specific_force(&b, p, &in, s->specific_force_mps2);
  }
}

void nps_finken_quadrotor_eulers(const struct nps_finken_quadrotor_state *s, double eulers_rad[3])
{
  const double *q = s->quat;
  const double sin_theta = 2 * (q[0] * q[2] - q[3] * q[1]);
  eulers_rad[0] = atan2(2 * (q[0] * q[1] + q[2] * q[3]), 1 - 2 * (q[1] * q[1] + q[2] * q[2]));
  eulers_rad[1] = asin(fmin(fmax(sin_theta, -1.0), 1.0));
  eulers_rad[2] = atan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] * q[2] + q[3] * q[3]));
}

void nps_finken_quadrotor_body_of_ltp(const struct nps_finken_quadrotor_state *s, const double v_ltp[3],
                                      double v_body[3])
{
  body_of_ltp(s->quat, v_ltp, v_body);
}
