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
 * @file nps_crosstalk.c
 * Sonar cross-talk geometry and timing (formulas in nps_crosstalk.h).
 */

#include "nps_crosstalk.h"

#include <math.h>

double nps_crosstalk_reading_m(double path_m, double trigger_offset_s, double speed_of_sound_mps)
{
  return 0.5 * (path_m + speed_of_sound_mps * trigger_offset_s);
}

bool nps_crosstalk_facing_cos(const double listener_pos_m[3], const double listener_dir[3],
                              const double emitter_pos_m[3], const double emitter_dir[3],
                              double cos_half_cone, double max_range_m, double *path_m)
{
  double to_emitter[3], to_listener[3];
  for (int i = 0; i < 3; i++) {
    to_emitter[i] = emitter_pos_m[i] - listener_pos_m[i];
    to_listener[i] = -to_emitter[i];
  }
  double dist = sqrt(to_emitter[0] * to_emitter[0] + to_emitter[1] * to_emitter[1] + to_emitter[2] * to_emitter[2]);
  if (path_m) {
    *path_m = dist;
  }
  return dist <= max_range_m && nps_crosstalk_in_cone(listener_dir, to_emitter, dist, cos_half_cone) &&
         nps_crosstalk_in_cone(emitter_dir, to_listener, dist, cos_half_cone);
}

bool nps_crosstalk_facing(const double listener_pos_m[3], const double listener_dir[3],
                          const double emitter_pos_m[3], const double emitter_dir[3],
                          double half_cone_rad, double max_range_m, double *path_m)
{
  return nps_crosstalk_facing_cos(listener_pos_m, listener_dir, emitter_pos_m, emitter_dir, cos(half_cone_rad),
                                  max_range_m, path_m);
}

bool nps_crosstalk_heard(double path_m, double trigger_offset_s, double speed_of_sound_mps,
                         double listen_window_s)
{
  return nps_crosstalk_arrives(path_m / speed_of_sound_mps, trigger_offset_s, listen_window_s);
}
