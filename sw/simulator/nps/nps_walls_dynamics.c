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
 * @file nps_walls_dynamics.c
 * Pure dynamics of one curtain plate: amplitude law, contact limit, stable sub-step and the integration
 * (equations in nps_walls.h).
 */

#include "nps_walls.h"

#include <math.h>

#define DEG_PER_RAD (180. / M_PI)

double nps_walls_amplitude_deg(double distance_m, double threshold_m, double max_amplitude_deg)
{
  if (!(distance_m < threshold_m)) {
    return 0.;
  }
  double x = 1. - (distance_m > 0. ? distance_m : 0.) / threshold_m;
  /* report section 2.3: f(x) = k (3.3 x^3 - 7 x^2 + 4.8 x), Horner form */
  return max_amplitude_deg * x * (4.8 + x * (-7. + 3.3 * x));
}

double nps_walls_contact_limit_rad(double distance_m, double radius_m, double copter_bottom_m,
                                   double hinge_height_m)
{
  double below = hinge_height_m - copter_bottom_m;
  if (below <= 0.) {
    return M_PI / 2.;
  }
  double gap = distance_m - radius_m;
  return gap > 0. ? atan(gap / below) : 0.;
}

double nps_walls_displacement_m(double hinge_height_m, double angle_rad, double z_m)
{
  double L = hinge_height_m;
  double bottom_z = L * (1. - cos(angle_rad));
  if (z_m > L || z_m < bottom_z) {
    return 0.;
  }
  return (L - z_m) * tan(angle_rad);
}

double nps_walls_inertia_kgm2(const struct nps_wall_params *p)
{
  return p->segment_mass_kg * p->hinge_height_m * p->hinge_height_m / 3.;
}

double nps_walls_restore_nm(const struct nps_wall_params *p)
{
  return p->curtain_mass_kg * NPS_WALLS_GRAVITY_M_S2 * p->hinge_height_m / 2.;
}

double nps_walls_substep_s(const struct nps_wall_params *p)
{
  double J = nps_walls_inertia_kgm2(p);
  double restore = nps_walls_restore_nm(p);
  if (!isfinite(J) || !isfinite(restore)) {
    return 0.;
  }
  /* time constants: inertia over each damping (friction slope at rest, D) and 1/omega of the stiffest spring */
  double damping = fmax(p->friction_nm / p->friction_velocity_rad_s, p->pid_d * DEG_PER_RAD);
  double stiffness = p->pid_p * DEG_PER_RAD + restore;
  double tau = sqrt(J / stiffness);
  if (damping > 0.) {
    tau = fmin(tau, J / damping);
  }
  return fmin(NPS_WALLS_MAX_SUBSTEP_S, 0.1 * tau);
}

/** Motor torque [N m] of the saturated PID; updates the integral unless that would deepen saturation. */
static double pid_torque(const struct nps_wall_params *p, struct nps_wall_segment *s, double h)
{
  double e = s->target_deg - s->angle_rad * DEG_PER_RAD;
  double rate_deg = s->rate_rad_s * DEG_PER_RAD;
  double integral = s->integral_deg_s + e * h;
  /* derivative on the measurement: no kick when the target jumps as a copter arrives */
  double u = p->pid_p * e + p->pid_i * integral - p->pid_d * rate_deg;
  if (fabs(u) > p->joint_force_nm && u * e > 0.) {
    /* conditional integration (anti-windup): hold the integral while saturated toward the error */
    u = p->pid_p * e + p->pid_i * s->integral_deg_s - p->pid_d * rate_deg;
  } else {
    s->integral_deg_s = integral;
  }
  return u > p->joint_force_nm ? p->joint_force_nm : (u < -p->joint_force_nm ? -p->joint_force_nm : u);
}

void nps_walls_segment_advance(const struct nps_wall *w, struct nps_wall_segment *s, double dt_s)
{
  if (!(dt_s > 0.)) {
    return;
  }
  int n = (int)ceil(dt_s / w->substep_s);
  double h = dt_s / n;
  for (int k = 0; k < n; k++) {
    double tau = s->driven ? pid_torque(&w->p, s, h)
                 : -w->p.friction_nm * tanh(s->rate_rad_s / w->p.friction_velocity_rad_s);
    tau -= w->restore_nm * sin(s->angle_rad);
    /* semi-implicit Euler: the new rate moves the angle */
    s->rate_rad_s += tau / w->inertia_kgm2 * h;
    s->angle_rad += s->rate_rad_s * h;
    if (s->angle_rad <= 0.) {
      /* the outer sheet backs the curtain: an inelastic stop at rest */
      s->angle_rad = 0.;
      s->rate_rad_s = s->rate_rad_s > 0. ? s->rate_rad_s : 0.;
    } else if (s->angle_rad >= s->limit_rad) {
      /* the plate rests against the copter's body (or hangs horizontal) */
      s->angle_rad = s->limit_rad;
      s->rate_rad_s = s->rate_rad_s < 0. ? s->rate_rad_s : 0.;
    }
    if (!s->driven && s->angle_rad < NPS_WALLS_REST_ANGLE_RAD && fabs(s->rate_rad_s) < NPS_WALLS_REST_RATE_RAD_S) {
      s->angle_rad = 0.;
      s->rate_rad_s = 0.;
      return;
    }
  }
}
