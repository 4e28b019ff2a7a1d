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
 * @file nps_floor.c
 * Floor materials and the material under a point (see nps_floor.h).
 */

#include "nps_floor.h"

#include <stdlib.h>
#include <string.h>

static const char *const material_names[NPS_FLOOR_MATERIALS] = { "none", "hard", "carpet", "foam" };

enum nps_floor_material nps_floor_material_from_name(const char *name)
{
  for (int m = NPS_FLOOR_HARD; name != NULL && m < NPS_FLOOR_MATERIALS; m++) {
    if (strcmp(name, material_names[m]) == 0) {
      return (enum nps_floor_material)m;
    }
  }
  return NPS_FLOOR_NONE;
}

const char *nps_floor_material_name(enum nps_floor_material material)
{
  return (material > NPS_FLOOR_NONE && material < NPS_FLOOR_MATERIALS) ? material_names[material]
         : material_names[NPS_FLOOR_NONE];
}

const char *nps_floor_material_names(void)
{
  return "hard, carpet or foam";
}

void nps_floor_init(struct nps_floor *floor)
{
  memset(floor, 0, sizeof * floor);
  floor->default_material = NPS_FLOOR_HARD;
}

int nps_floor_copy(struct nps_floor *dst, const struct nps_floor *src)
{
  *dst = *src;
  dst->regions = NULL;
  if (src->num_regions > 0) {
    dst->regions = malloc((size_t)src->num_regions * sizeof * dst->regions);
    if (dst->regions == NULL) {
      dst->num_regions = 0;
      return -1;
    }
    memcpy(dst->regions, src->regions, (size_t)src->num_regions * sizeof * dst->regions);
  }
  return 0;
}

void nps_floor_free(struct nps_floor *floor)
{
  free(floor->regions);
  floor->regions = NULL;
  floor->num_regions = 0;
}

enum nps_floor_material nps_floor_material_at(const struct nps_floor *floor, double x_m, double y_m)
{
  for (int i = 0; i < floor->num_regions; i++) {
    const struct nps_floor_region *r = &floor->regions[i];
    if (x_m >= r->x0_m && x_m <= r->x1_m && y_m >= r->y0_m && y_m <= r->y1_m) {
      return r->material;
    }
  }
  return floor->default_material;
}
