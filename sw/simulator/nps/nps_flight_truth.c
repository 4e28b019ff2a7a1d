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
 * @file nps_flight_truth.c
 * The ground truth of a lab's readings (see nps_flight_truth.h).
 */

#include "nps_flight_truth.h"
#include "nps_floor.h"

int nps_flight_truth_sonar(const struct nps_arena *a, int rx_id, const double origin_m[3], const double dir[3],
                           struct nps_flight_sonar_truth *out)
{
  const int rx = nps_arena_copter_index(a, rx_id);
  if (rx < 0) {
    return -1;
  }
  const struct nps_arena_copter *c = &a->copters[rx];
  struct nps_ray_hit hit;
  out->hit_kind = nps_raycast_range(a, origin_m, dir, NPS_FLIGHT_TRUTH_RANGE_M, rx_id, NPS_RAYCAST_NO_ID, &hit);
  out->true_range_m = hit.kind == NPS_HIT_NOTHING ? NPS_FLIGHT_TRUTH_RANGE_M : hit.range_m;
  out->wall_dist_m = nps_raycast_wall_dist(a, c->pos_m);
  out->floor = nps_floor_material_at(&a->floor, c->pos_m[0], c->pos_m[1]);

  struct nps_facing_sonar facing[NPS_FLIGHT_TRUTH_MAX_FACING];
  const int found = nps_raycast_facing_nearest(a, rx_id, origin_m, dir, a->sonar_cos_half_angle, a->sonar_range_m,
                                               facing, NPS_FLIGHT_TRUTH_MAX_FACING);
  out->listed = 0;
  for (int i = 0; i < found && i < NPS_FLIGHT_TRUTH_MAX_FACING; i++) {
    const struct nps_facing_sonar *f = &facing[i];
    if (!nps_raycast_line_blocked(a, f->emitter_pos_m, origin_m, f->copter_id, rx_id, NULL)) {
      out->facing_copter[out->listed] = f->copter_id;
      out->facing_sonar[out->listed] = (int)f->sonar;
      out->facing_path_m[out->listed] = f->path_m;
      out->listed++;
    }
  }
  /* beyond the list (more than a few facing sonars: a crowd), the farthest are counted without a line-of-sight test */
  out->facing = out->listed + (found > NPS_FLIGHT_TRUTH_MAX_FACING ? found - NPS_FLIGHT_TRUTH_MAX_FACING : 0);
  return 0;
}

void nps_flight_truth_sonar_geometry(const struct nps_arena *a, double *offset_m, double *half_angle_rad,
                                     double *range_m)
{
  *offset_m = a->sonar_offset_m;
  *half_angle_rad = a->sonar_half_angle_rad;
  *range_m = a->sonar_range_m;
}
