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
 * @file nps_floor.h
 * The arena's floor materials: a default material and axis-aligned rectangles of other materials. The downward
 * sonar's context value ctx_floor is the code of the material under the copter, so that sensor-model effects can
 * depend on it (condition="ctx_floor == 3"). Codes are fixed and ordered by how much of a sonar pulse the material
 * absorbs, so that a cut "ctx_floor >= 2" means "a soft floor":
 *   0  none:   not a downward sonar reading (horizontal sonars, ranging)
 *   1  hard:   concrete, linoleum, wood, tiles: a specular floor, a strong echo (the default)
 *   2  carpet: a textile floor covering
 *   3  foam:   a foam or gym mat
 */

#ifndef NPS_FLOOR_H
#define NPS_FLOOR_H

enum nps_floor_material {
  NPS_FLOOR_NONE = 0,
  NPS_FLOOR_HARD = 1,
  NPS_FLOOR_CARPET = 2,
  NPS_FLOOR_FOAM = 3,
  NPS_FLOOR_MATERIALS
};

/** A rectangle [x0, x1] x [y0, y1] of one material, arena frame [m]. */
struct nps_floor_region {
  double x0_m, y0_m, x1_m, y1_m;
  enum nps_floor_material material;
  int line;                        /**< XML line of its <region> (0: from code) */
};

/** The floor: regions (no two overlap) of their material, the default material everywhere else. */
struct nps_floor {
  enum nps_floor_material default_material;   /**< NPS_FLOOR_HARD unless the arena says otherwise */
  struct nps_floor_region *regions;           /**< owned; NULL when there are none */
  int num_regions;
  int line;                                   /**< XML line of <floor> (0: none given) */
};

/** The material of a name ("hard", "carpet", "foam"), or NPS_FLOOR_NONE for any other text. */
enum nps_floor_material nps_floor_material_from_name(const char *name);

/** The name of a material ("hard", ...), "none" for NPS_FLOOR_NONE and codes out of range. */
const char *nps_floor_material_name(enum nps_floor_material material);

/** "hard, carpet or foam": the names a file may use, for messages. */
const char *nps_floor_material_names(void);

/** A floor of the default material (hard) without regions. */
void nps_floor_init(struct nps_floor *floor);

/** A deep copy of src into dst (dst's old regions are not freed). @return 0, or -1 on ENOMEM */
int nps_floor_copy(struct nps_floor *dst, const struct nps_floor *src);

/** Release the regions; the floor is then the default material everywhere. */
void nps_floor_free(struct nps_floor *floor);

/**
 * The material at (x_m, y_m): the first region (in file order) whose closed rectangle holds the point, else the
 * default material. A linear scan: arenas have a few regions.
 */
enum nps_floor_material nps_floor_material_at(const struct nps_floor *floor, double x_m, double y_m);

#endif /* NPS_FLOOR_H */
