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
 * @file nps_walls.h
 * Curtain-wall dynamics (report section 2.3): every plate hangs on a hinge along its top edge. While the
 * nearest copter is within `threshold`, a PID drives the hinge angle toward the amplitude law
 * k (3.3 x^3 - 7 x^2 + 4.8 x), x = 1 - distance / threshold; otherwise the plate swings free against
 * Coulomb friction and gravity pulls it back to vertical.
 *
 * Equation of motion of one plate (angle theta [rad], > 0 into the arena):
 *   J theta'' = tau_motor_or_friction - restore sin(theta),  J = segmentMass L^2 / 3,  restore = curtainMass g L / 2
 *   driven: tau = sat(P e + I int(e) - D theta'_deg, jointForce), e = target - theta in degrees
 *   free:   tau = -friction tanh(theta' / frictionVelocity)
 * Stops: theta >= 0 (the outer plastic sheet backs the curtain), theta <= the contact angle at which the
 * plate would touch the driving copter's body (or 90 deg). Semi-implicit Euler with sub-steps no longer
 * than nps_wall.substep_s.
 *
 * Also the Paparazzi-NPS-shaped hook over one simulator-wide arena: nps_walls_init / nps_walls_run_step.
 */

#ifndef NPS_WALLS_H
#define NPS_WALLS_H

#include "nps_arena.h"

/** Longest integration sub-step [s] (accuracy; stability is ensured by nps_walls_substep_s). */
#define NPS_WALLS_MAX_SUBSTEP_S 0.01
/**
 * Shortest sub-step an arena may need [s]: 10^4 sub-steps per plate in a 10 ms step. Shorter ones come from
 * parameters no curtain has (a PID_P of 1e56) and would stall the simulation; the arena check refuses them.
 */
#define NPS_WALLS_MIN_SUBSTEP_S 1e-6
/** A free plate closer to rest than this is set exactly to rest [rad] (0.006 deg, 40 um at 0.4 m). */
#define NPS_WALLS_REST_ANGLE_RAD 1e-4
/** ... if it also turns slower than this [rad/s]. */
#define NPS_WALLS_REST_RATE_RAD_S 1e-3
/** Standard gravity [m/s^2]. */
#define NPS_WALLS_GRAVITY_M_S2 9.80665

/**
 * The report's amplitude law: target hinge angle [deg] for a copter at distance_m,
 * k (3.3 x^3 - 7 x^2 + 4.8 x) with x = 1 - distance / threshold; 0 at or beyond threshold.
 */
double nps_walls_amplitude_deg(double distance_m, double threshold_m, double max_amplitude_deg);

/**
 * Largest hinge angle [rad] before the plate touches a copter body: the plate at height z is
 * (L - z) tan(theta) inward of its rest line, so the lowest point of the body (copter_bottom_m) meets
 * it when (L - z) tan(theta) = distance - radius. pi/2 if the body is entirely above the hinge.
 */
double nps_walls_contact_limit_rad(double distance_m, double radius_m, double copter_bottom_m,
                                   double hinge_height_m);

/** Horizontal inward displacement [m] of a plate at hinge angle angle_rad at height z_m: (L - z) tan(angle) where the plate reaches that height, else 0. */
double nps_walls_displacement_m(double hinge_height_m, double angle_rad, double z_m);

/** Hinge inertia of a plate about its top edge, segmentMass L^2 / 3 (thin plate, L = hingeHeight) [kg m^2]. */
double nps_walls_inertia_kgm2(const struct nps_wall_params *p);

/** Scale of the gravity torque pulling a plate back to vertical, curtainMass g L / 2 [N m]. */
double nps_walls_restore_nm(const struct nps_wall_params *p);

/**
 * Largest stable sub-step [s] for these parameters: a tenth of the fastest time constant, at most
 * NPS_WALLS_MAX_SUBSTEP_S; 0 when the inertia or the restoring torque is not a finite number.
 */
double nps_walls_substep_s(const struct nps_wall_params *p);

/** Advance one plate by dt_s [s] with its current driven/target_deg/limit_rad (pure over the structs). */
void nps_walls_segment_advance(const struct nps_wall *w, struct nps_wall_segment *s, double dt_s);

/**
 * One wall step at time_s [s]: find each plate's nearest copter through the grid (no copter x segment
 * scan), set the PID targets and contact limits, and integrate over time_s minus the previous step's
 * time (nothing is integrated on the first call). Only the plates of nps_arena.active_segs are visited (a
 * free plate at rest stays so): a plate's angle or rate may be set by hand before the first step, not later.
 * The copter index must be current (copters changed in place are followed by nps_arena_poses_moved, nps_arena.h).
 * @return 0, or -1 with errno EINVAL when time_s is not finite or goes backwards
 */
int nps_arena_walls_step(struct nps_arena *a, double time_s);

/**
 * Set every plate's state as another simulator stepped it to time_s: hinge angle [rad], rate [rad/s] and PID
 * integral [deg s] in arena order (nps_arena.segs). The next wall step integrates from this state and time.
 * @return 0, or -1 with errno EINVAL when n is not the arena's plate count or time_s is not finite
 */
int nps_arena_walls_set_state(struct nps_arena *a, double time_s, const double *angle_rad, const double *rate_rad_s,
                              const double *integral_deg_s, int n);

/* ---- NPS-shaped hook over one simulator-wide arena ---- */

/** Load the arena (replacing any previous one). @return 0, or -1 (message from nps_walls_error()) */
int nps_walls_init(const char *arena_file);

/** The last error of the hook ("" if none). */
const char *nps_walls_error(void);

/** Give this step's copters to the simulator-wide arena. @return 0 or -1 (see nps_arena_set_copters) */
int nps_walls_set_copters(const struct nps_arena_copter *copters, int n);

/** Advance the simulator-wide walls to time [s]; a no-op before nps_walls_init. */
void nps_walls_run_step(double time);

/** The simulator-wide arena (NULL before nps_walls_init), for ray casts and snapshots. */
struct nps_arena *nps_walls_arena(void);

/** Free the simulator-wide arena. */
void nps_walls_free(void);

#endif /* NPS_WALLS_H */
