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
 * @file nps_crosstalk.h
 * Sonar cross-talk from geometry: when another copter's sonar is heard directly, and what it then reads.
 *
 * A sonar triggered at t0 times the first echo and reports c * (arrival - t0) / 2. The pulse of another
 * sonar, triggered at t0 + dt and travelling the one-way path L straight to this sensor, arrives at
 * t0 + dt + L / c, so the reading is (L + c dt) / 2: half the path when both fire together, which is the
 * lab report's "halving" (finken-environment-report.md, section 3.2).
 */

#ifndef NPS_CROSSTALK_H
#define NPS_CROSSTALK_H

#include <math.h>
#include <stdbool.h>

/** Speed of sound in dry air at 20 degC [m/s] (343.2 m/s, ISO 9613-1 reference atmosphere; rounded). */
#define NPS_CROSSTALK_SPEED_OF_SOUND_MPS 343.0

/**
 * The reading caused by a directly heard pulse [m]: (path_m + c * trigger_offset_s) / 2.
 * @param trigger_offset_s  emitter's trigger time minus this sensor's trigger time [s]
 */
double nps_crosstalk_reading_m(double path_m, double trigger_offset_s, double speed_of_sound_mps);

/**
 * Whether two sonars face each other: each lies within the other's beam cone and they are at most
 * max_range_m apart. Directions need not be normalised (zero vectors never face).
 * @param path_m  receives the one-way path length [m] (may be NULL)
 */
bool nps_crosstalk_facing(const double listener_pos_m[3], const double listener_dir[3],
                          const double emitter_pos_m[3], const double emitter_dir[3],
                          double half_cone_rad, double max_range_m, double *path_m);

/** nps_crosstalk_facing with the cone given by cos(half_cone_rad), for callers that test many pairs. */
bool nps_crosstalk_facing_cos(const double listener_pos_m[3], const double listener_dir[3],
                              const double emitter_pos_m[3], const double emitter_dir[3],
                              double cos_half_cone, double max_range_m, double *path_m);

/**
 * One half of the facing test: whether `dir` points at a point `to` away (dist_m = |to|) within the cone,
 * i.e. (dir . to) / (|dir| dist_m) >= cos_half_cone. A zero dir or distance never qualifies. Inline: the facing
 * search's exact test, with its vectors in registers.
 */
static inline bool nps_crosstalk_in_cone(const double dir[3], const double to[3], double dist_m, double cos_half_cone)
{
  double dir_norm = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (dir_norm <= 0.0 || dist_m <= 0.0) {
    return false;
  }
  double cos_angle = (dir[0] * to[0] + dir[1] * to[1] + dir[2] * to[2]) / (dir_norm * dist_m);
  return cos_angle >= cos_half_cone;
}

/**
 * nps_crosstalk_heard for a pulse whose travel time L / c is known (travel_s), e.g. one emitter's several pulses:
 * 0 <= dt + travel_s <= window.
 */
static inline bool nps_crosstalk_arrives(double travel_s, double trigger_offset_s, double listen_window_s)
{
  const double arrival_s = trigger_offset_s + travel_s;
  return arrival_s >= 0.0 && arrival_s <= listen_window_s;
}

/**
 * Whether a facing emitter's pulse arrives while this sensor listens: 0 <= dt + L / c <= window.
 * @param listen_window_s  time this sensor waits for an echo after its trigger [s]
 */
bool nps_crosstalk_heard(double path_m, double trigger_offset_s, double speed_of_sound_mps,
                         double listen_window_s);

#endif /* NPS_CROSSTALK_H */
