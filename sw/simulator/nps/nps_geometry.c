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
 * @file nps_geometry.c
 * Small exact geometry for the arena (see nps_geometry.h).
 */

#include "nps_geometry.h"

#include <math.h>
#include <stddef.h>

/** Depth-first quadtree stack: 3 siblings wait per level, 64 levels halve any arena below 1e-15 m. */
#define CLEARANCE_STACK_LEN (3 * 64 + 4)

static double cross2(const double o[2], const double a[2], const double b[2])
{
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static double dot3(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double nps_geometry_nearest_on_segment(const double p[2], const double a[2], const double b[2], double q[2])
{
  double ab[2] = { b[0] - a[0], b[1] - a[1] };
  double ap[2] = { p[0] - a[0], p[1] - a[1] };
  double len2 = ab[0] * ab[0] + ab[1] * ab[1];
  double s = len2 > 0. ? (ap[0] * ab[0] + ap[1] * ab[1]) / len2 : 0.;
  if (s < 0.) {
    s = 0.;
  } else if (s > 1.) {
    s = 1.;
  }
  q[0] = a[0] + s * ab[0];
  q[1] = a[1] + s * ab[1];
  double dx = ap[0] - s * ab[0];
  double dy = ap[1] - s * ab[1];
  return dx * dx + dy * dy;
}

double nps_geometry_point_segment_dist2(const double p[2], const double a[2], const double b[2])
{
  double q[2];
  return nps_geometry_nearest_on_segment(p, a, b, q);
}

/** q lies on the closed segment [a, b], given that a, b, q are collinear. */
static int on_collinear_segment(const double a[2], const double b[2], const double q[2])
{
  return fmin(a[0], b[0]) <= q[0] && q[0] <= fmax(a[0], b[0]) &&
         fmin(a[1], b[1]) <= q[1] && q[1] <= fmax(a[1], b[1]);
}

static int touch(const double a[2], const double b[2], const double q[2], double at[2])
{
  if (cross2(a, b, q) == 0. && on_collinear_segment(a, b, q)) {
    if (at) {
      at[0] = q[0];
      at[1] = q[1];
    }
    return 1;
  }
  return 0;
}

int nps_geometry_segments_intersect(const double p1[2], const double p2[2],
                                    const double q1[2], const double q2[2], double at[2])
{
  double d1 = cross2(q1, q2, p1);
  double d2 = cross2(q1, q2, p2);
  double d3 = cross2(p1, p2, q1);
  double d4 = cross2(p1, p2, q2);
  if (((d1 > 0. && d2 < 0.) || (d1 < 0. && d2 > 0.)) && ((d3 > 0. && d4 < 0.) || (d3 < 0. && d4 > 0.))) {
    if (at) {
      double s = d1 / (d1 - d2);
      at[0] = p1[0] + s * (p2[0] - p1[0]);
      at[1] = p1[1] + s * (p2[1] - p1[1]);
    }
    return 1;
  }
  return touch(q1, q2, p1, at) || touch(q1, q2, p2, at) || touch(p1, p2, q1, at) || touch(p1, p2, q2, at);
}

double nps_geometry_polygon_area2(const double (*pts)[2], int n)
{
  double a2 = 0.;
  for (int i = 0; i < n; i++) {
    const double *p = pts[i];
    const double *q = pts[(i + 1) % n];
    a2 += p[0] * q[1] - q[0] * p[1];
  }
  return a2;
}

int nps_geometry_point_in_polygon(const double (*pts)[2], int n, const double p[2])
{
  int inside = 0;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const double *a = pts[i];
    const double *b = pts[j];
    if ((a[1] > p[1]) != (b[1] > p[1]) &&
        p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) {
      inside = !inside;
    }
  }
  return inside;
}

double nps_geometry_polygon_clearance(const double (*pts)[2], int n, const double p[2])
{
  double best2 = INFINITY;
  for (int i = 0; i < n; i++) {
    double d2 = nps_geometry_point_segment_dist2(p, pts[i], pts[(i + 1) % n]);
    if (d2 < best2) {
      best2 = d2;
    }
  }
  double d = sqrt(best2);
  return nps_geometry_point_in_polygon(pts, n, p) ? d : -d;
}

/** A polygon for its clearance. */
struct polygon {
  const double (*pts)[2];
  int n;
};

/** nps_geometry_polygon_clearance of a struct polygon, as nps_geometry_max_clearance calls it. */
static double polygon_clearance(const void *ctx, const double p[2])
{
  const struct polygon *poly = ctx;
  return nps_geometry_polygon_clearance(poly->pts, poly->n, p);
}

double nps_geometry_polygon_max_clearance(const double (*pts)[2], int n, double tol_m, double stop_at_m)
{
  double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY }, at[2];
  for (int i = 0; i < n; i++) {
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], pts[i][k]);
      hi[k] = fmax(hi[k], pts[i][k]);
    }
  }
  const struct polygon poly = { pts, n };
  return nps_geometry_max_clearance(lo, hi, polygon_clearance, &poly, tol_m, stop_at_m, at);
}

double nps_geometry_max_clearance(const double lo[2], const double hi[2], nps_geometry_clearance_fn clearance,
                                  const void *ctx, double tol_m, double stop_at_m, double at[2])
{
  /* cells: centre x, centre y, half size */
  double stack[CLEARANCE_STACK_LEN][3];
  int top = 0;
  stack[top][0] = 0.5 * (lo[0] + hi[0]);
  stack[top][1] = 0.5 * (lo[1] + hi[1]);
  stack[top][2] = 0.5 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
  top++;
  double best = -INFINITY;
  while (top > 0) {
    top--;
    double c[2] = { stack[top][0], stack[top][1] };
    double half = stack[top][2];
    double here = clearance(ctx, c);
    if (here > best) {
      best = here;
      at[0] = c[0];
      at[1] = c[1];
      if (best >= stop_at_m) {
        return best;
      }
    }
    if (here + half * M_SQRT2 <= best + tol_m || top + 4 > CLEARANCE_STACK_LEN) {
      continue;
    }
    double q = 0.5 * half;
    for (int k = 0; k < 4; k++) {
      stack[top][0] = c[0] + ((k & 1) ? q : -q);
      stack[top][1] = c[1] + ((k & 2) ? q : -q);
      stack[top][2] = q;
      top++;
    }
  }
  return best;
}

double nps_geometry_ray_rect(const double o[3], const double d[3], const struct nps_geometry_rect *r)
{
  double denom = dot3(r->normal, d);
  if (denom == 0.) {
    return INFINITY;
  }
  double oc[3] = { r->corner[0] - o[0], r->corner[1] - o[1], r->corner[2] - o[2] };
  double t = dot3(r->normal, oc) / denom;
  if (!(t >= 0.)) {
    return INFINITY;
  }
  double w[3] = { o[0] + t * d[0] - r->corner[0], o[1] + t * d[1] - r->corner[1], o[2] + t * d[2] - r->corner[2] };
  double s = dot3(w, r->e1);
  double u = dot3(w, r->e2);
  const double tol = NPS_GEOMETRY_EDGE_TOL_M;
  if (s < -tol || s > r->len1_m + tol || u < -tol || u > r->len2_m + tol) {
    return INFINITY;
  }
  return t;
}

/** nps_geometry_ray_cylinder; always inlined, so that the range-only caller (normal NULL) has no normal's work. */
static inline __attribute__((always_inline)) double ray_cylinder(const double o[3], const double d[3],
                                                                 const double centre[3], double radius_m,
                                                                 double half_height_m, double normal[3])
{
  double ox = o[0] - centre[0], oy = o[1] - centre[1], oz = o[2] - centre[2];
  double r2 = radius_m * radius_m;
  double c = ox * ox + oy * oy - r2;
  if (c <= 0. && fabs(oz) <= half_height_m) {
    if (normal) {
      normal[0] = -d[0];
      normal[1] = -d[1];
      normal[2] = -d[2];
    }
    return 0.;
  }
  double best = INFINITY;
  double nbest[3] = { 0., 0., 0. };
  /* side: |(ox, oy) + t (dx, dy)|^2 = r^2, entry root of a t^2 + b t + c = 0 (b = 2 (o . d)) */
  double a = d[0] * d[0] + d[1] * d[1];
  if (a > 0. && c > 0.) {
    double b = 2. * (ox * d[0] + oy * d[1]);
    double disc = b * b - 4. * a * c;
    if (disc >= 0. && b < 0.) {
      /* entry root in the cancellation-free form 2c / (-b + sqrt(disc)) */
      double t = 2. * c / (-b + sqrt(disc));
      double z = oz + t * d[2];
      if (fabs(z) <= half_height_m) {
        best = t;
        nbest[0] = (ox + t * d[0]) / radius_m;
        nbest[1] = (oy + t * d[1]) / radius_m;
        nbest[2] = 0.;
      }
    }
  }
  /* caps: the one facing the ray origin */
  if (d[2] != 0. && fabs(oz) > half_height_m) {
    double zc = oz > 0. ? half_height_m : -half_height_m;
    double t = (zc - oz) / d[2];
    if (t >= 0. && t < best) {
      double x = ox + t * d[0], y = oy + t * d[1];
      if (x * x + y * y <= r2) {
        best = t;
        nbest[0] = 0.;
        nbest[1] = 0.;
        nbest[2] = oz > 0. ? 1. : -1.;
      }
    }
  }
  if (normal && best < INFINITY) {
    normal[0] = nbest[0];
    normal[1] = nbest[1];
    normal[2] = nbest[2];
  }
  return best;
}

double nps_geometry_ray_cylinder(const double o[3], const double d[3], const double centre[3],
                                 double radius_m, double half_height_m, double normal[3])
{
  return ray_cylinder(o, d, centre, radius_m, half_height_m, normal);
}

double nps_geometry_ray_cylinder_range(const double o[3], const double d[3], const double centre[3],
                                       double radius_m, double half_height_m)
{
  return ray_cylinder(o, d, centre, radius_m, half_height_m, NULL);
}

int nps_geometry_segment_enters_box(const double a[2], const double b[2], const double lo[2], const double hi[2])
{
  double t_in = 0., t_out = 1.;   /* the part a + t (b - a), t in (t_in, t_out), inside the open box */
  for (int k = 0; k < 2; k++) {
    const double d = b[k] - a[k];
    if (d == 0.) {
      if (!(a[k] > lo[k] && a[k] < hi[k])) {
        return 0;
      }
      continue;
    }
    const double t_lo = (lo[k] - a[k]) / d, t_hi = (hi[k] - a[k]) / d;
    t_in = fmax(t_in, fmin(t_lo, t_hi));
    t_out = fmin(t_out, fmax(t_lo, t_hi));
  }
  return t_in < t_out;
}
