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
 * @file nps_finken_quadrotor.h
 * Rigid-body flight model of a FINken quadrotor: pure C, no globals, no Paparazzi header.
 * Paparazzi's NPS flies it through nps_fdm_finken.c (module fdm_finken); the unit tests call it directly.
 *
 * Frames (Paparazzi's): local tangent plane NED (x north, y east, z down) [m], body FRD (x forward, y right,
 * z down); attitude the unit quaternion ltp -> body (qi, qx, qy, qz; Hamilton product, ZYX Euler angles);
 * body rates p, q, r [rad/s]. The ground is the plane z = 0 (the flight plan's ground altitude).
 *
 * Model, per step of dt:
 * - rotors: normalised speed w_i in [0, 1] follows the motor command c_i (clamped to [0, 1]) with a first-order lag
 *   (time constant rotor_tau_s, integrated exactly); thrust T_i = max_thrust_n * w_i^2 along -z body at
 *   (x_i, y_i); reaction torque about z body spin_i * torque_coef_m * T_i (spin_i = +1 for a rotor turning
 *   counter-clockwise seen from above, -1 clockwise);
 * - linear drag -drag_i * (v - wind) per body axis;
 * - rigid body: m dv/dt = R^T F_body + m g (NED), I dw/dt = tau - w x I w (principal axes), dq/dt = q (x) (0, w) / 2;
 *   integrated with one classical Runge-Kutta step (rotor thrusts held over it), quaternion renormalised;
 * - ground: a step that ends below z = 0 ends on the ground: z = 0, velocity and body rates zero, roll and pitch
 *   zero (heading kept) -- a landing gear that stops the copter flat. It lifts off when thrust exceeds weight.
 * Earth rotation is neglected (inertial = ECEF-relative rates and accelerations).
 */

#ifndef NPS_FINKEN_QUADROTOR_H
#define NPS_FINKEN_QUADROTOR_H

#include <stdbool.h>

#define NPS_FINKEN_QUADROTOR_ROTORS 4

/*
 * Defaults of a FINken (estimates, see docs/paparazzi-fdm.md); an airframe overrides them in
 * <section name="SIMULATOR" prefix="NPS_"> (define FINKEN_MASS etc.) read by nps_fdm_finken.c.
 */
#ifndef NPS_FINKEN_MASS
#define NPS_FINKEN_MASS 0.5            ///< total mass [kg]
#endif
#ifndef NPS_FINKEN_ARM_LENGTH
#define NPS_FINKEN_ARM_LENGTH 0.12     ///< centre of mass to rotor axis [m] (0.24 m motor to motor)
#endif
#ifndef NPS_FINKEN_MAX_THRUST
#define NPS_FINKEN_MAX_THRUST 3.0      ///< thrust of one rotor at full speed (command 1) [N]; thrust to weight 2.45
#endif
#ifndef NPS_FINKEN_TORQUE_COEF
#define NPS_FINKEN_TORQUE_COEF 0.01    ///< rotor drag torque per thrust k_m / k_f [N m / N] (5 inch propellers)
#endif
#ifndef NPS_FINKEN_ROTOR_TAU
#define NPS_FINKEN_ROTOR_TAU 0.03      ///< time constant of the rotor speed [s]
#endif
#ifndef NPS_FINKEN_IXX
#define NPS_FINKEN_IXX 1.5e-3          ///< roll inertia [kg m^2]
#endif
#ifndef NPS_FINKEN_IYY
#define NPS_FINKEN_IYY 1.5e-3          ///< pitch inertia [kg m^2]
#endif
#ifndef NPS_FINKEN_IZZ
#define NPS_FINKEN_IZZ 2.8e-3          ///< yaw inertia [kg m^2]
#endif
#ifndef NPS_FINKEN_DRAG_XY
#define NPS_FINKEN_DRAG_XY 0.13        ///< linear drag along the body x and y axes [N / (m/s)]
#endif
#ifndef NPS_FINKEN_DRAG_Z
#define NPS_FINKEN_DRAG_Z 0.2          ///< linear drag along the body z axis [N / (m/s)]
#endif
#ifndef NPS_FINKEN_GRAVITY
#define NPS_FINKEN_GRAVITY 9.81        ///< [m/s^2] (Paparazzi's PPRZ_ISA_GRAVITY is 9.80665; JSBSim's ltp_g 9.81)
#endif

struct nps_finken_quadrotor_params {
  double mass_kg;
  double inertia_kgm2[3];            ///< Ixx, Iyy, Izz (principal axes = body axes) [kg m^2]
  double rotor_pos_m[NPS_FINKEN_QUADROTOR_ROTORS][2]; ///< rotor i at x (forward), y (right) in the body frame [m]
  double rotor_spin[NPS_FINKEN_QUADROTOR_ROTORS];     ///< +1 counter-clockwise seen from above, -1 clockwise
  double max_thrust_n;               ///< thrust of one rotor at w = 1 [N]
  double torque_coef_m;              ///< yaw torque per thrust [m]
  double rotor_tau_s;                ///< rotor speed lag [s] (0: the rotor follows the command at once)
  double drag_ns_m[3];               ///< linear drag along body x, y, z [N / (m/s)]
  double gravity_mps2;
};

struct nps_finken_quadrotor_state {
  double pos_m[3];                   ///< position, NED [m] (z = 0 is the ground)
  double vel_mps[3];                 ///< velocity, NED [m/s]
  double quat[4];                    ///< attitude ltp -> body, qi qx qy qz (unit)
  double rates_rps[3];               ///< body rates p, q, r [rad/s]
  double rotor_speed[NPS_FINKEN_QUADROTOR_ROTORS]; ///< normalised rotor speeds w_i [0..1]
  bool on_ground;                    ///< the last step ended on the ground
  /* outputs of the last step, at its end */
  double accel_mps2[3];              ///< acceleration, NED [m/s^2]
  double specific_force_mps2[3];     ///< what an accelerometer reads, body frame [m/s^2] (-g on z at rest)
  double rot_accel_rps2[3];          ///< body angular acceleration [rad/s^2]
  double thrust_n;                   ///< total rotor thrust [N]
};

/**
 * Rotor geometry from motor-mixing coefficients (Paparazzi's MOTOR_MIXING_ROLL_COEF, _PITCH_COEF, _YAW_COEF: a
 * positive roll coefficient lifts a rotor on the left, a positive pitch one a rotor in front, a positive yaw one a
 * rotor whose torque turns the copter right, i.e. one turning counter-clockwise): rotor i at arm_m from the centre
 * in the direction (pitch_i, -roll_i), spinning sign(yaw_i). So the flight model and the mixing agree on the
 * layout by construction. A rotor with zero roll and pitch coefficients sits at the centre.
 */
extern void nps_finken_quadrotor_set_rotors(struct nps_finken_quadrotor_params *p, const double *roll_coef,
    const double *pitch_coef, const double *yaw_coef, double arm_m);

/**
 * Parameters from the NPS_FINKEN_* defines above (or the airframe's, when its header is included first), rotors
 * laid out as Paparazzi's QUAD_X motor mixing orders them (front left CW, front right CCW, back right CW,
 * back left CCW). Inline, so that the defines are those of the file that calls it.
 */
static inline void nps_finken_quadrotor_params_default(struct nps_finken_quadrotor_params *p)
{
  static const double roll[NPS_FINKEN_QUADROTOR_ROTORS] = { 181, -181, -181, 181 };
  static const double pitch[NPS_FINKEN_QUADROTOR_ROTORS] = { 181, 181, -181, -181 };
  static const double yaw[NPS_FINKEN_QUADROTOR_ROTORS] = { -128, 128, -128, 128 };
  p->mass_kg = NPS_FINKEN_MASS;
  p->inertia_kgm2[0] = NPS_FINKEN_IXX;
  p->inertia_kgm2[1] = NPS_FINKEN_IYY;
  p->inertia_kgm2[2] = NPS_FINKEN_IZZ;
  p->max_thrust_n = NPS_FINKEN_MAX_THRUST;
  p->torque_coef_m = NPS_FINKEN_TORQUE_COEF;
  p->rotor_tau_s = NPS_FINKEN_ROTOR_TAU;
  p->drag_ns_m[0] = NPS_FINKEN_DRAG_XY;
  p->drag_ns_m[1] = NPS_FINKEN_DRAG_XY;
  p->drag_ns_m[2] = NPS_FINKEN_DRAG_Z;
  p->gravity_mps2 = NPS_FINKEN_GRAVITY;
  nps_finken_quadrotor_set_rotors(p, roll, pitch, yaw, NPS_FINKEN_ARM_LENGTH);
}

/** At rest on the ground at (north, east), heading psi [rad], rotors stopped. */
extern void nps_finken_quadrotor_init(struct nps_finken_quadrotor_state *s, double north_m, double east_m,
                                      double psi_rad);

/** The rotor command (equal on all rotors, rotors at that speed) whose thrust holds the weight: sqrt(m g / (4 T_max)). */
extern double nps_finken_quadrotor_hover_command(const struct nps_finken_quadrotor_params *p);

/**
 * Advance by dt_s under the motor commands (Paparazzi's normalised commands, 0..1, in motor-mixing order; values
 * outside are clamped, NaN counts as 0) in the wind wind_ned_mps (NULL: no wind). dt_s <= 0 changes nothing.
 */
extern void nps_finken_quadrotor_step(struct nps_finken_quadrotor_state *s, const struct nps_finken_quadrotor_params *p,
                                      const double commands[NPS_FINKEN_QUADROTOR_ROTORS], const double *wind_ned_mps,
                                      double dt_s);

/** ZYX Euler angles phi, theta, psi [rad] of the attitude quaternion. */
extern void nps_finken_quadrotor_eulers(const struct nps_finken_quadrotor_state *s, double eulers_rad[3]);

/** v_body = R v_ltp, R the rotation ltp -> body of the state's quaternion. */
extern void nps_finken_quadrotor_body_of_ltp(const struct nps_finken_quadrotor_state *s, const double v_ltp[3],
    double v_body[3]);

#endif /* NPS_FINKEN_QUADROTOR_H */
