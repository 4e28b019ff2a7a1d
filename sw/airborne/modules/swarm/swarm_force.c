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
 * @file modules/swarm/swarm_force.c
 * The FINken attraction-repulsion law (see swarm_force.h for the law and its sources).
 */

#include "modules/swarm/swarm_force.h"

#include <math.h>
#include <string.h>

/** The attraction a d of an echo, 0 for none (a negative distance). */
static float attraction_of(const struct swarm_params *params, float attraction_m)
{
  return attraction_m >= 0.f ? params->a * attraction_m : 0.f;
}

/** The distance sqrt(c / 2) at which the repulsion b d exp(-d^2 / c) peaks [m]. */
static float peak_of(const struct swarm_params *params)
{
  return sqrtf(0.5f * params->c_m2);
}

/** The repulsion b d exp(-d^2 / c) at d_m (at or beyond the peak). */
static float repulsion_at(const struct swarm_params *params, float d_m)
{
  return params->b * d_m * expf(-d_m * d_m / params->c_m2);
}

/**
 * An echo's term a d_att - b d exp(-d^2 / c), with the repulsion at the peak from `peak`, brought up to the params'
 * b and c first (compared by their bits: the same bits give the same repulsion).
 */
static float echo_term_cached(const struct swarm_params *params, struct swarm_peak_repulsion *peak,
                              float attraction_m, float repulsion_m)
{
  if (!peak->known || memcmp(&peak->b, &params->b, sizeof(params->b)) != 0 ||
      memcmp(&peak->c_m2, &params->c_m2, sizeof(params->c_m2)) != 0) {
    peak->known = true;
    peak->b = params->b;
    peak->c_m2 = params->c_m2;
    peak->peak_m = peak_of(params);
    peak->repulsion = repulsion_at(params, peak->peak_m);
  }
  /* b d exp(-d^2 / c) peaks at d = sqrt(c / 2); closer echoes (and a NaN reading) keep the peak (swarm_force.h) */
  const float repulsion = repulsion_m > peak->peak_m ? repulsion_at(params, repulsion_m) : peak->repulsion;
  return attraction_of(params, attraction_m) - repulsion;
}

float swarm_echo_term_m(const struct swarm_params *params, float attraction_m, float repulsion_m)
{
  struct swarm_peak_repulsion fresh = { .known = false };
  return echo_term_cached(params, &fresh, attraction_m, repulsion_m);
}

void swarm_sonar_direction_ned(float yaw_rad, float heading_rad, struct FloatVect2 *u_ned)
{
  /* both clockwise seen from above: the yaw from north, the sonar heading from the nose */
  const float bearing_rad = yaw_rad + heading_rad;
  u_ned->x = cosf(bearing_rad);
  u_ned->y = sinf(bearing_rad);
}

void swarm_cohesion_ned(const struct swarm_params *params, const struct swarm_echo *echoes, unsigned echo_nb,
                        float yaw_rad, uint32_t now_us, bool use_wall_detector,
                        struct swarm_peak_repulsion *peak, struct FloatVect2 *sum_ned)
{
  sum_ned->x = 0.f;
  sum_ned->y = 0.f;
  for (unsigned i = 0; i < echo_nb; i++) {
    const struct swarm_echo *e = &echoes[i];
    const float age_s = (float)(int32_t)(now_us - e->stamp_us) * 1e-6f;
    if (!e->valid || age_s > params->echo_timeout_s || e->target_class == WALL_DETECTOR_NO_ECHO) {
      continue;  // nothing detected within the sonar's range: no swarm member on this side
    }
    const float attraction_m = use_wall_detector ? e->attraction_m : e->repulsion_m;
    struct FloatVect2 u;
    swarm_sonar_direction_ned(yaw_rad, e->heading_rad, &u);
    const float term_m = echo_term_cached(params, peak, attraction_m, e->repulsion_m);
    sum_ned->x += term_m * u.x;
    sum_ned->y += term_m * u.y;
  }
}

void swarm_target_ned(const struct swarm_target *target, float time_s, struct FloatVect2 *target_ned)
{
  const float angle_rad = target->period_s > 0.f ? 2.f * (float)M_PI * time_s / target->period_s : 0.f;
  /* the circle is drawn in ENU (east = x, north = y); NED swaps the two */
  target_ned->x = target->centre_north_m + target->radius_m * sinf(angle_rad);
  target_ned->y = target->centre_east_m + target->radius_m * cosf(angle_rad);
}

void swarm_velocity_ned(const struct swarm_params *params, const struct FloatVect2 *cohesion_ned,
                        const struct FloatVect2 *pos_ned, const struct FloatVect2 *target_ned,
                        struct FloatVect2 *velocity_ned)
{
  const float target_gain = params->target_weight * params->a;
  velocity_ned->x = params->gain_per_s * (params->cohesion_weight * cohesion_ned->x +
                                          target_gain * (target_ned->x - pos_ned->x));
  velocity_ned->y = params->gain_per_s * (params->cohesion_weight * cohesion_ned->y +
                                          target_gain * (target_ned->y - pos_ned->y));
  /* |v| without hypotf's care for overflow: speeds of metres per second square far inside a float's range */
  const float speed_mps = sqrtf(velocity_ned->x * velocity_ned->x + velocity_ned->y * velocity_ned->y);
  if (speed_mps > params->max_speed_mps) {
    velocity_ned->x *= params->max_speed_mps / speed_mps;
    velocity_ned->y *= params->max_speed_mps / speed_mps;
  }
}
