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
 * @file nps_obstacle.h
 * Interior obstacles of an arena: a pillar, a table, a cupboard. Each is static and solid, a vertical prism from the
 * floor up to its height over a simple polygon or a circle. Frame: the arena's ENU frame [m].
 */

#ifndef NPS_OBSTACLE_H
#define NPS_OBSTACLE_H

#ifdef __cplusplus
extern "C" {
#endif

/** Outline of an obstacle's footprint. */
enum nps_obstacle_shape {
  NPS_OBSTACLE_POLYGON = 0,
  NPS_OBSTACLE_CIRCLE
};

/** One obstacle: its footprint and height, and (from nps_obstacle_finish) its bounding box. */
struct nps_obstacle {
  enum nps_obstacle_shape shape;
  double height_m;               /**< top above the floor [m] */
  double centre_m[2];            /**< circle centre [m] */
  double radius_m;               /**< circle radius [m] */
  double (*corners)[2];          /**< polygon corners, not repeating the first (counter-clockwise once finished) */
  int *corner_lines;             /**< XML line of each corner (0: from code) */
  int num_corners;
  int line;                      /**< XML line of <obstacle> (0: from code) */
  double lo_m[2], hi_m[2];       /**< footprint's bounding box [m] */
};

/** Put a polygon's corners in counter-clockwise order (their lines with them) and fill the bounding box. */
void nps_obstacle_finish(struct nps_obstacle *o);

/** A deep copy of src into dst (corners owned by dst). @return 0, or -1 out of memory */
int nps_obstacle_copy(struct nps_obstacle *dst, const struct nps_obstacle *src);

/** Release what o owns. */
void nps_obstacle_free(struct nps_obstacle *o);

/** Horizontal distance [m] from p to the footprint's outline: positive outside, negative inside. */
double nps_obstacle_signed_dist(const struct nps_obstacle *o, const double p[2]);

/**
 * Distance along the ray org + t d (d unit), t >= 0, to the obstacle's sides or top; INFINITY on a miss.
 * @param[out] normal  outward unit normal at the hit
 */
double nps_obstacle_ray(const struct nps_obstacle *o, const double org[3], const double d[3], double normal[3]);

/**
 * Keep a body of radius radius_m centred at pos_m[0..1] outside the footprint: if it reaches in, move it straight
 * out to touch it. @return 1 if moved, else 0
 */
int nps_obstacle_push_out(const struct nps_obstacle *o, double pos_m[2], double radius_m);

/**
 * The footprint's outline as at most max_points corners xy[k][0..1] [m], counter-clockwise once finished: a circle as
 * the regular polygon of max_points corners. @return the footprint's number of corners (a polygon's may be more than
 * were written)
 */
int nps_obstacle_outline(const struct nps_obstacle *o, double (*xy)[2], int max_points);

/** Whether two finished obstacles' footprints overlap or touch. */
int nps_obstacles_overlap(const struct nps_obstacle *a, const struct nps_obstacle *b);

#ifdef __cplusplus
}
#endif

#endif /* NPS_OBSTACLE_H */
