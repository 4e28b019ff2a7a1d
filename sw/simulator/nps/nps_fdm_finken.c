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
 * NPS flight model of a FINken quadrotor (module fdm_finken): Paparazzi glue around the pure rigid-body model
 * nps_finken_quadrotor.c. It steps the model with NPS's motor commands (0..1, motor-mixing order) and fills `fdm`
 * in every frame NPS's sensors, INS/AHRS bypasses and display read: ECEF, the local NED frame about the flight
 * plan's origin (NAV_LAT0, NAV_LON0, ground at NAV_ALT0 above MSL), LLA, attitude, rates, accelerations (the
 * accelerometer's with gravity), ISA pressure and temperature, airspeed in the wind.
 *
 * Compiled only in a Paparazzi build (nps_fdm.h, generated/airframe.h, generated/flight_plan.h).
 *
 * Parameters: the NPS_FINKEN_* defines of nps_finken_quadrotor.h, overridden in the airframe's
 * <section name="SIMULATOR" prefix="NPS_">. The rotor layout is the airframe's motor mixing (MOTOR_MIXING_TYPE
 * QUAD_X or QUAD_PLUS, or its own MOTOR_MIXING_*_COEF), four rotors.
 *
 * Log: with the environment variable FINKEN_FDM_LOG=<path>, a CSV of the flight (time, NED position and velocity,
 * attitude, rates, height, ground contact, thrust, motor commands; and the autopilot's side: its mode, the horizontal
 * guidance speed setpoint, the vertical position setpoint, the estimated NED position and speed) at FINKEN_FDM_LOG_HZ rows per simulated second (default 50). Nothing is written otherwise.
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nps_fdm.h"
#include "nps_fdm_finken.h"
#include "nps_arena_contact.h"

#include "generated/airframe.h"
#include "generated/flight_plan.h"
#include "math/pprz_algebra_double.h"
#include "math/pprz_algebra_float.h"
#include "math/pprz_geodetic_double.h"
#include "math/pprz_isa.h"
#include "modules/actuators/motor_mixing_types.h"

#include "nps_finken_quadrotor.h"   /* after airframe.h: the airframe's NPS_FINKEN_* defines come first */

#ifndef ROTORCRAFT_FIRMWARE
#error "fdm_finken is a quadrotor flight model: rotorcraft firmware only"
#endif
#include "autopilot.h"
#include "firmwares/rotorcraft/guidance/guidance_h.h"
#include "firmwares/rotorcraft/guidance/guidance_v.h"
#include "state.h"

#if defined(MOTOR_MIXING_NB_MOTOR) && MOTOR_MIXING_NB_MOTOR != NPS_FINKEN_QUADROTOR_ROTORS
#error "fdm_finken flies four rotors: MOTOR_MIXING_NB_MOTOR must be 4"
#endif

/** Magnetic field (normalised, NED) the magnetometer sees: the airframe's, else Toulouse's as fdm_rover has it. */
#if defined(AHRS_H_X)
#define NPS_FINKEN_H_X AHRS_H_X
#define NPS_FINKEN_H_Y AHRS_H_Y
#define NPS_FINKEN_H_Z AHRS_H_Z
#elif defined(INS_H_X)
#define NPS_FINKEN_H_X INS_H_X
#define NPS_FINKEN_H_Y INS_H_Y
#define NPS_FINKEN_H_Z INS_H_Z
#else
#define NPS_FINKEN_H_X 0.4912
#define NPS_FINKEN_H_Y 0.1225
#define NPS_FINKEN_H_Z 0.8624
#endif

#ifndef NPS_FINKEN_START_NORTH
#define NPS_FINKEN_START_NORTH 0.  ///< start position, north of the flight plan's origin [m]
#endif
#ifndef NPS_FINKEN_START_EAST
#define NPS_FINKEN_START_EAST 0.   ///< start position, east of the flight plan's origin [m]
#endif
#ifndef NPS_FINKEN_START_HEADING
#define NPS_FINKEN_START_HEADING 0. ///< start heading, from north toward east [deg]
#endif

struct NpsFdm fdm;

static struct {
  struct nps_finken_quadrotor_params params;
  struct nps_finken_quadrotor_state state;
  struct LtpDef_d ltp_def;            ///< the flight plan's origin, on the ground
  double wind_ned[3];                 ///< [m/s]
  double temperature_sl_c;            ///< ISA temperature at sea level [deg C] (nps_fdm_set_temperature)
  double commands[NPS_FINKEN_QUADROTOR_ROTORS];
  unsigned long steps;
  FILE *log;
  unsigned long log_every;            ///< steps between two log rows
} finken;

static void fill_fdm(void);

static void init_params(void)
{
  nps_finken_quadrotor_params_default(&finken.params);
#if defined(MOTOR_MIXING_ROLL_COEF) && defined(MOTOR_MIXING_PITCH_COEF) && defined(MOTOR_MIXING_YAW_COEF)
  const double roll[] = MOTOR_MIXING_ROLL_COEF, pitch[] = MOTOR_MIXING_PITCH_COEF, yaw[] = MOTOR_MIXING_YAW_COEF;
  nps_finken_quadrotor_set_rotors(&finken.params, roll, pitch, yaw, NPS_FINKEN_ARM_LENGTH);
#endif
}

static void init_ltp(void)
{
  /* like the INS: NAV_ALT0 is the ground above MSL, NAV_MSL0 the geoid above the ellipsoid (mm) */
  struct LlaCoor_d origin = {
    .lat = RadOfDeg((double)NAV_LAT0 / 1e7),
    .lon = RadOfDeg((double)NAV_LON0 / 1e7),
    .alt = ((double)NAV_ALT0 + (double)NAV_MSL0) / 1000.,
  };
  ltp_def_from_lla_d(&finken.ltp_def, &origin);
  finken.ltp_def.hmsl = (double)NAV_ALT0 / 1000.;
  fdm.ltp_g = (struct DoubleVect3) { 0., 0., finken.params.gravity_mps2 };
  fdm.ltp_h = (struct DoubleVect3) { NPS_FINKEN_H_X, NPS_FINKEN_H_Y, NPS_FINKEN_H_Z };
}

static void open_log(double dt)
{
  const char *path = getenv("FINKEN_FDM_LOG");
  if (path == NULL || path[0] == '\0') {
    return;
  }
  const char *hz_text = getenv("FINKEN_FDM_LOG_HZ");
  const double hz = hz_text ? atof(hz_text) : 50.;
  finken.log_every = hz > 0. ? (unsigned long)fmax(1., round(1. / (hz * dt))) : 1;
  finken.log = fopen(path, "w");
  if (finken.log == NULL) {
    perror(path);
    return;
  }
  fprintf(finken.log, "t_s,north_m,east_m,down_m,vn_mps,ve_mps,vd_mps,phi_rad,theta_rad,psi_rad,p_rps,q_rps,r_rps,"
          "agl_m,on_ground,thrust_n,cmd0,cmd1,cmd2,cmd3,ap_mode,sp_vn_mps,sp_ve_mps,sp_down_m,est_north_m,est_east_m,"
          "est_down_m,est_vn_mps,est_ve_mps\n");
  fflush(finken.log);
  printf("fdm_finken: logging to %s every %lu steps\n", path, finken.log_every);
}

static void log_row(void)
{
  const struct nps_finken_quadrotor_state *s = &finken.state;
  const struct NedCoor_f *est = stateGetPositionNed_f(), *est_v = stateGetSpeedNed_f();
  fprintf(finken.log, "%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%d,%.4f,"
          "%.4f,%.4f,%.4f,%.4f,%d,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f\n",
          fdm.time, s->pos_m[0], s->pos_m[1], s->pos_m[2], s->vel_mps[0], s->vel_mps[1], s->vel_mps[2],
          fdm.ltp_to_body_eulers.phi, fdm.ltp_to_body_eulers.theta, fdm.ltp_to_body_eulers.psi,
          s->rates_rps[0], s->rates_rps[1], s->rates_rps[2], fdm.agl, s->on_ground ? 1 : 0, s->thrust_n,
          finken.commands[0], finken.commands[1], finken.commands[2], finken.commands[3],
          (int)autopilot_get_mode(),
          SPEED_FLOAT_OF_BFP(guidance_h.sp.speed.x), SPEED_FLOAT_OF_BFP(guidance_h.sp.speed.y),
          POS_FLOAT_OF_BFP(guidance_v.z_sp), est->x, est->y, est->z, est_v->x, est_v->y);
  fflush(finken.log);   /* simsitl is stopped by a signal: every row is on disk when it is written */
}

void nps_fdm_init(double dt)
{
  memset(&fdm, 0, sizeof(fdm));
  fdm.init_dt = dt;
  fdm.curr_dt = dt;
  fdm.time = 0.;
  fdm.pressure_sl = PPRZ_ISA_SEA_LEVEL_PRESSURE;
  finken.temperature_sl_c = PPRZ_ISA_SEA_LEVEL_TEMP + PPRZ_ISA_ABS_NULL;
  init_params();
  init_ltp();
  nps_fdm_finken_place(NPS_FINKEN_START_NORTH, NPS_FINKEN_START_EAST, RadOfDeg(NPS_FINKEN_START_HEADING));
  open_log(dt);
  printf("fdm_finken: %.3f kg, %.2f N per rotor, hover command %.3f\n", finken.params.mass_kg,
         finken.params.max_thrust_n, nps_finken_quadrotor_hover_command(&finken.params));
}

void nps_fdm_finken_place(double north_m, double east_m, double heading_rad)
{
  nps_finken_quadrotor_init(&finken.state, north_m, east_m, heading_rad);
  /* at rest on the ground: the accelerometer reads the ground's push before the first step */
  const double up[3] = { 0., 0., -finken.params.gravity_mps2 };
  nps_finken_quadrotor_body_of_ltp(&finken.state, up, finken.state.specific_force_mps2);
  fill_fdm();
}

void nps_fdm_finken_take_contact(double north_m, double east_m)
{
  const double to[2] = { north_m, east_m };
  nps_arena_contact_take(finken.state.pos_m, finken.state.vel_mps, to);
  fill_fdm();
}

/* (motor_commands: `commands` is the autopilot's global in this build) */
void nps_fdm_run_step(bool launch __attribute__((unused)), double *motor_commands, int commands_nb)
{
  for (int i = 0; i < NPS_FINKEN_QUADROTOR_ROTORS; i++) {
    finken.commands[i] = i < commands_nb ? motor_commands[i] : 0.;
  }
  nps_finken_quadrotor_step(&finken.state, &finken.params, finken.commands, finken.wind_ned, fdm.init_dt);
  finken.steps++;
  fdm.time = finken.steps * fdm.init_dt;
  fill_fdm();
  if (finken.log != NULL && finken.steps % finken.log_every == 0) {
    log_row();
  }
}

/** ltp_to_body composed with the rotation ecef -> ltp of the origin. */
static void ecef_to_body_quat(struct DoubleQuat *out, struct DoubleQuat *ltp_to_body)
{
  struct FloatRMat ecef_to_ltp_f;
  for (int i = 0; i < 9; i++) {
    ecef_to_ltp_f.m[i] = (float)finken.ltp_def.ltp_of_ecef.m[i];
  }
  struct FloatQuat q_f;
  float_quat_of_rmat(&q_f, &ecef_to_ltp_f);
  struct DoubleQuat ecef_to_ltp = { q_f.qi, q_f.qx, q_f.qy, q_f.qz };
  double_quat_comp(out, &ecef_to_ltp, ltp_to_body);
}

static void fill_fdm(void)
{
  const struct nps_finken_quadrotor_state *s = &finken.state;
  fdm.on_ground = s->on_ground;

  /* position */
  fdm.ltpprz_pos = (struct NedCoor_d) { s->pos_m[0], s->pos_m[1], s->pos_m[2] };
  ecef_of_ned_point_d(&fdm.ecef_pos, &finken.ltp_def, &fdm.ltpprz_pos);
  lla_of_ecef_d(&fdm.lla_pos, &fdm.ecef_pos);
  fdm.lla_pos_pprz = fdm.lla_pos;
  fdm.lla_pos_geod = fdm.lla_pos;
  fdm.lla_pos_geoc = fdm.lla_pos;
  fdm.hmsl = finken.ltp_def.hmsl - s->pos_m[2];
  fdm.agl = -s->pos_m[2];

  /* velocity and acceleration (the local frame is the flight plan's: ltp and ltpprz are the same) */
  fdm.ltpprz_ecef_vel = (struct NedCoor_d) { s->vel_mps[0], s->vel_mps[1], s->vel_mps[2] };
  fdm.ltpprz_ecef_accel = (struct NedCoor_d) { s->accel_mps2[0], s->accel_mps2[1], s->accel_mps2[2] };
  fdm.ltp_ecef_vel = fdm.ltpprz_ecef_vel;
  fdm.ltp_ecef_accel = fdm.ltpprz_ecef_accel;
  ecef_of_ned_vect_d(&fdm.ecef_ecef_vel, &finken.ltp_def, &fdm.ltpprz_ecef_vel);
  ecef_of_ned_vect_d(&fdm.ecef_ecef_accel, &finken.ltp_def, &fdm.ltpprz_ecef_accel);
  nps_finken_quadrotor_body_of_ltp(s, s->vel_mps, (double *)&fdm.body_ecef_vel);
  nps_finken_quadrotor_body_of_ltp(s, s->accel_mps2, (double *)&fdm.body_ecef_accel);
  fdm.body_inertial_accel = fdm.body_ecef_accel;   /* Earth rotation neglected */
  fdm.body_accel = (struct DoubleVect3) {
    s->specific_force_mps2[0], s->specific_force_mps2[1], s->specific_force_mps2[2]
  };

  /* attitude */
  fdm.ltp_to_body_quat = (struct DoubleQuat) { s->quat[0], s->quat[1], s->quat[2], s->quat[3] };
  double_eulers_of_quat(&fdm.ltp_to_body_eulers, &fdm.ltp_to_body_quat);
  fdm.ltpprz_to_body_quat = fdm.ltp_to_body_quat;
  fdm.ltpprz_to_body_eulers = fdm.ltp_to_body_eulers;
  ecef_to_body_quat(&fdm.ecef_to_body_quat, &fdm.ltp_to_body_quat);

  /* rates */
  fdm.body_ecef_rotvel = (struct DoubleRates) { s->rates_rps[0], s->rates_rps[1], s->rates_rps[2] };
  fdm.body_ecef_rotaccel = (struct DoubleRates) { s->rot_accel_rps2[0], s->rot_accel_rps2[1], s->rot_accel_rps2[2] };
  fdm.body_inertial_rotvel = fdm.body_ecef_rotvel;
  fdm.body_inertial_rotaccel = fdm.body_ecef_rotaccel;

  /* air: ISA at the height above MSL, the wind NPS's atmosphere sets */
  fdm.wind = (struct DoubleVect3) { finken.wind_ned[0], finken.wind_ned[1], finken.wind_ned[2] };
  const double air_ltp[3] = {
    s->vel_mps[0] - finken.wind_ned[0], s->vel_mps[1] - finken.wind_ned[1], s->vel_mps[2] - finken.wind_ned[2]
  };
  double air_body[3];
  nps_finken_quadrotor_body_of_ltp(s, air_ltp, air_body);
  const double airspeed = sqrt(air_body[0] * air_body[0] + air_body[1] * air_body[1] + air_body[2] * air_body[2]);
  fdm.pressure = pprz_isa_pressure_of_altitude(fdm.hmsl);
  fdm.temperature = finken.temperature_sl_c - PPRZ_ISA_TEMP_LAPS_RATE * fdm.hmsl;
  const double rho = pprz_isa_density_of_pressure(fdm.pressure, fdm.temperature);
  fdm.dynamic_pressure = 0.5 * rho * airspeed * airspeed;
  fdm.total_pressure = fdm.pressure + fdm.dynamic_pressure;
  fdm.airspeed = airspeed;   /* true airspeed: at the FINken's heights it is the equivalent one to 1 % */
  fdm.aoa = airspeed > 1e-3 ? atan2(air_body[2], air_body[0]) : 0.;
  fdm.sideslip = airspeed > 1e-3 ? asin(air_body[1] / airspeed) : 0.;
}

void nps_fdm_set_wind(double speed, double dir)
{
  /* as nps_fdm_fixedwing_sim: dir is the direction the wind blows toward, from north toward east */
  finken.wind_ned[0] = speed * cos(dir);
  finken.wind_ned[1] = speed * sin(dir);
  finken.wind_ned[2] = 0.;
}

void nps_fdm_set_wind_ned(double wind_north, double wind_east, double wind_down)
{
  finken.wind_ned[0] = wind_north;
  finken.wind_ned[1] = wind_east;
  finken.wind_ned[2] = wind_down;
}

void nps_fdm_set_turbulence(double wind_speed __attribute__((unused)),
                            int turbulence_severity __attribute__((unused)))
{
  /* no turbulence model: the wind is steady */
}

void nps_fdm_set_temperature(double temp, double h)
{
  /* ISA lapse rate through temp [deg C] at h [m] above MSL */
  finken.temperature_sl_c = temp + PPRZ_ISA_TEMP_LAPS_RATE * h;
}
