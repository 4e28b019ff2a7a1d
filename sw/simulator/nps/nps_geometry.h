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
 * @file nps_geometry.h
 * Small exact geometry for the arena: 2D segments and polygons, 3D ray intersections with rectangles
 * and vertical cylinders. Pure functions; lengths in metres, directions unit vectors.
 */

#ifndef NPS_GEOMETRY_H
#define NPS_GEOMETRY_H

/** Tolerance on the edges of a rectangle hit, so a ray through the seam of two segments hits one [m]. */
#define NPS_GEOMETRY_EDGE_TOL_M 1e-9

/** The point q of the segment [a, b] nearest to p (a when the segment is a point); returns |p - q|^2 [m^2]. */
double nps_geometry_nearest_on_segment(const double p[2], const double a[2], const double b[2], double q[2]);

/** Squared 2D distance [m^2] from point p to the segment [a, b]. */
double nps_geometry_point_segment_dist2(const double p[2], const double a[2], const double b[2]);

/**
 * Do the closed 2D segments [p1, p2] and [q1, q2] share a point?
 * @param[out] at  one shared point when they do (may be NULL)
 * @return 1 if they intersect or touch, 0 otherwise
 */
int nps_geometry_segments_intersect(const double p1[2], const double p2[2],
                                    const double q1[2], const double q2[2], double at[2]);

/** Twice the signed area [m^2] of the polygon pts[0..n-1] (not repeating the first point); > 0 if CCW. */
double nps_geometry_polygon_area2(const double (*pts)[2], int n);

/** Distance [m] from p to the boundary of the polygon pts[0..n-1], positive inside it and negative outside. */
double nps_geometry_polygon_clearance(const double (*pts)[2], int n, const double p[2]);

/** 1 if p is strictly inside the simple polygon pts[0..n-1] (crossing-number rule), else 0. */
int nps_geometry_point_in_polygon(const double (*pts)[2], int n, const double p[2]);

/**
 * 1 if the segment [a, b] passes through the open box (lo[0], hi[0]) x (lo[1], hi[1]), else 0: a segment along
 * the box's border or through a corner only does not (Liang-Barsky clipping to the open box).
 */
int nps_geometry_segment_enters_box(const double a[2], const double b[2], const double lo[2], const double hi[2]);

/**
 * Largest clearance [m] of any interior point of a simple polygon from its boundary (the radius of the
 * largest inscribed circle), found by branch and bound on a quadtree: a cell whose centre has clearance c
 * and half-diagonal h cannot hold more than c + h (the clearance is 1-Lipschitz).
 * @param tol_m  absolute accuracy of the answer [m]
 * @param stop_at_m  return as soon as a point with at least this clearance is found (INFINITY: never)
 */
double nps_geometry_polygon_max_clearance(const double (*pts)[2], int n, double tol_m, double stop_at_m);

/** A 1-Lipschitz clearance: distance from p to the nearest boundary, negative where p is not free [m]. */
typedef double (*nps_geometry_clearance_fn)(const void *ctx, const double p[2]);

/**
 * The largest clearance in the box [lo, hi] and a point at with it (nps_geometry_polygon_max_clearance's search,
 * for any clearance): the centre of the largest free circle, to tol_m.
 */
double nps_geometry_max_clearance(const double lo[2], const double hi[2], nps_geometry_clearance_fn clearance,
                                  const void *ctx, double tol_m, double stop_at_m, double at[2]);

/** Geometry of a planar rectangle in 3D: corner + s e1 + u e2, s in [0, len1], u in [0, len2]. */
struct nps_geometry_rect {
  double corner[3];   /**< one corner [m] */
  double e1[3];       /**< unit edge direction */
  double len1_m;      /**< length along e1 [m] */
  double e2[3];       /**< unit edge direction, orthogonal to e1 */
  double len2_m;      /**< length along e2 [m] */
  double normal[3];   /**< unit normal, e1 x e2 up to sign */
};

/**
 * Distance along the ray o + t d (d unit) to the rectangle, either side; INFINITY when it misses or is
 * parallel. Edges are inclusive within NPS_GEOMETRY_EDGE_TOL_M.
 */
double nps_geometry_ray_rect(const double o[3], const double d[3], const struct nps_geometry_rect *r);

/**
 * Distance along the ray o + t d (d unit) to the solid vertical cylinder of the given centre, radius and
 * half height; 0 if o is inside; INFINITY on a miss.
 * @param[out] normal  outward unit normal at the hit (may be NULL); -d when o is inside
 */
double nps_geometry_ray_cylinder(const double o[3], const double d[3], const double centre[3],
                                 double radius_m, double half_height_m, double normal[3]);

/** nps_geometry_ray_cylinder(o, d, centre, radius_m, half_height_m, NULL): the same distance, no normal's work. */
double nps_geometry_ray_cylinder_range(const double o[3], const double d[3], const double centre[3],
                                       double radius_m, double half_height_m);

/**
 * Whether sqrt(norm2) is exactly 1, without the root: the correctly rounded root of a double is 1 only for 1 and
 * for 1 + 2^-52 (its root 1 + 2^-53 - 2^-106 lies below the midpoint 1 + 2^-53 of 1 and the next double); the
 * double 1 - 2^-53 below 1 has the root 1 - 2^-54 - 2^-109, below the midpoint of 1 - 2^-53 and 1. test_raycast
 * checks it against sqrt for the doubles around 1. A ray of such a direction needs no normalisation.
 */
static inline int nps_geometry_root_is_one(double norm2)
{
  return norm2 == 1. || norm2 == 1. + 0x1p-52;
}

#endif /* NPS_GEOMETRY_H */
