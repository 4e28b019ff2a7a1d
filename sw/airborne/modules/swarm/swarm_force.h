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
 * @file modules/swarm/swarm_force.h
 * The FINken attraction-repulsion swarm law over sonar echoes (pure functions).
 *
 * Sources. Gazi and Passino's aggregation law, x_i' = sum_j g(x_i - x_j) with
 *   g(y) = -y (a - b exp(-|y|^2 / c))   (linear attraction, bounded repulsion;
 * V. Gazi, K. M. Passino, "Stability analysis of swarms", IEEE Trans. Automatic Control 48(4):692-697, 2003),
 * as the FINken V-REP swarm applies it to what its four sonars detect (ovgu-FINken/Simulation, branch ws16Env,
 * finken_swarm/source/swarm/finken_util.lua and finken_util_with_Virtual_Ranging_Wall_Check.lua:
 * getAttractionRepulsionPosition sums y (a - b exp(-|y|^2 / c)) over the detected objects, multiplies the sum by
 * wCohesion and adds wTarget a times the target offset; prepareConfig: a = 1, b = 4, c = 1.5 m^2,
 * wCohesion = 0.8, wTarget = 0.2). Each sonar reports the nearest object in its cone within 3 m ("Swarm in
 * Formation" documentation, 2015, section 3.1); a sonar that detects nothing adds no term. So the attraction of
 * one echo is linear in its distance and local only through the sonar's range: an echo attracts with a d up
 * to the range (3 m here, the sonar maximum of report section 3.2), and "no echo" attracts and repels nothing.
 * (That documentation's appendix names "function III, linearly bounded attraction and unbounded repulsion";
 * its code, which the lab flew, is the law above. We follow the code.)
 *
 * The law. Each echo at distance d in the unit direction u (from the copter toward the echo) is a swarm member
 * at y = d u:
 *   f = u (a d - b d' exp(-d'^2 / c)),  d' = max(d, sqrt(c / 2)),
 * zero at d = sqrt(c ln(b / a)) = 1.44 m, repulsion closer, attraction further. The attraction part a d u is
 * taken only from echoes usable for attraction (copters when the wall detector is used, every echo
 * otherwise); the repulsion part from every echo. One change to the law: Gazi and Passino's repulsion, made
 * for point agents, peaks at d = sqrt(c / 2) (0.87 m, 2.1 with the FINken's b and c) and vanishes at contact,
 * so a copter pressed toward a wall would be pushed back less the closer it gets. Echoes closer than
 * sqrt(c / 2) therefore repel with the peak value, b sqrt(c / 2) exp(-1/2): the push away from an obstacle never
 * weakens as it comes closer. The commanded velocity (local NED) is
 *   v = gain (cohesion_weight sum_sonars f + target_weight a (p_target - p)),  bounded to max_speed,
 * the original's weighting with its target term a (p_target - p).
 *
 * Walls as swarm members. Without the detector a wall is a member like a copter: within the sonar's range it
 * holds the copter at 1.44 m (attracted beyond, repelled closer, with stiffness cohesion_weight f'(1.44 m) =
 * 0.8 x 2.77 = 2.2 per metre against the target's 0.2 per metre): the swarm sticks to the walls it sees. Walls
 * on opposite sides within range pull both ways, so in an arena narrower than twice the range the copters are
 * held where the walls' terms cancel (in the 3 m wide SwarmLab, about the middle line).
 */

#ifndef SWARM_FORCE_H
#define SWARM_FORCE_H

#include "math/pprz_algebra_float.h"
#include "modules/wall_detector/wall_detector_reading.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Parameters of the law (each mirrors a SWARM_* define and a setting). */
struct swarm_params {
  float a;                ///< attraction gain [1]
  float b;                ///< repulsion gain [1]
  float c_m2;             ///< repulsion width [m^2]
  float cohesion_weight;  ///< weight of the swarm term [1]
  float target_weight;    ///< weight of the target term [1]
  float gain_per_s;       ///< commanded velocity per metre of weighted force [1/s]
  float max_speed_mps;    ///< bound of the commanded horizontal speed [m/s]
  float echo_timeout_s;   ///< echoes older than this are dropped [s]
};

/** The target: a point moving on a circle around a centre (radius 0: the centre itself). */
struct swarm_target {
  float centre_east_m;   ///< centre, local ENU east [m]
  float centre_north_m;  ///< centre, local ENU north [m]
  float radius_m;        ///< radius of the circle [m]
  float period_s;        ///< time of one counter-clockwise revolution [s]
};

/** The latest reading of one sonar, as the wall detector published it. */
struct swarm_echo {
  bool valid;                              ///< a reading was received
  uint32_t stamp_us;                       ///< time of the reading [us]
  float heading_rad;                       ///< sonar direction, body frame (front 0, right pi/2, left -pi/2) [rad]
  enum wall_detector_class target_class;   ///< the detector's class
  float attraction_m;                      ///< the detector's distance for attraction, negative when none [m]
  float repulsion_m;                       ///< the reading [m]
};

/** The repulsion of an echo at or below the peak distance sqrt(c / 2), b sqrt(c / 2) exp(-1/2) as swarm_echo_term_m
 * computes it, kept with the b and c it is of (in a swarm a third of the echoes are that close): computed again when
 * their bits change. */
struct swarm_peak_repulsion {
  bool known;       ///< the fields below are of b and c_m2
  float b;          ///< the repulsion gain it is of [1]
  float c_m2;       ///< the repulsion width it is of [m^2]
  float peak_m;     ///< sqrt(c / 2) [m]
  float repulsion;  ///< b peak exp(-peak^2 / c)
};

/**
 * Signed magnitude of one echo's term along u: a d_att - b d exp(-d^2 / c) with d = max(d_rep, sqrt(c / 2))
 * (positive: toward the echo).
 * @param attraction_m distance for attraction, negative for none [m]
 * @param repulsion_m distance for repulsion [m]
 */
extern float swarm_echo_term_m(const struct swarm_params *params, float attraction_m, float repulsion_m);

/** Unit vector (north, east) of a sonar at body-frame heading_rad on a copter with yaw yaw_rad (from north to east). */
extern void swarm_sonar_direction_ned(float yaw_rad, float heading_rad, struct FloatVect2 *u_ned);

/**
 * Sum of the echo terms (north, east) [m] over the fresh echoes (not "no echo" readings: nothing there).
 * @param use_wall_detector attraction from the detector's copter echoes only (true) or from every echo (false)
 * @param peak cache of the repulsion at the peak, kept by the caller
 */
extern void swarm_cohesion_ned(const struct swarm_params *params, const struct swarm_echo *echoes, unsigned echo_nb,
                               float yaw_rad, uint32_t now_us, bool use_wall_detector,
                               struct swarm_peak_repulsion *peak, struct FloatVect2 *sum_ned);

/** Target position (north, east) [m] at time time_s. */
extern void swarm_target_ned(const struct swarm_target *target, float time_s, struct FloatVect2 *target_ned);

/** Commanded velocity (north, east) [m/s] from the cohesion sum, the position and the target (all NED). */
extern void swarm_velocity_ned(const struct swarm_params *params, const struct FloatVect2 *cohesion_ned,
                               const struct FloatVect2 *pos_ned, const struct FloatVect2 *target_ned,
                               struct FloatVect2 *velocity_ned);

#ifdef __cplusplus
}
#endif

#endif /* SWARM_FORCE_H */
