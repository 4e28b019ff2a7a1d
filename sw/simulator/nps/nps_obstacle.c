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
 * @file nps_obstacle.c
 * Interior obstacles: their geometry against rays, bodies and each other (see nps_obstacle.h).
 */

#include "nps_obstacle.h"
#include "nps_geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void reverse_corners(struct nps_obstacle *o)
{
  for (int i = 0, j = o->num_corners - 1; i < j; i++, j--) {
    const double x = o->corners[i][0], y = o->corners[i][1];
    o->corners[i][0] = o->corners[j][0];
    o->corners[i][1] = o->corners[j][1];
    o->corners[j][0] = x;
    o->corners[j][1] = y;
    if (o->corner_lines != NULL) {
      const int line = o->corner_lines[i];
      o->corner_lines[i] = o->corner_lines[j];
      o->corner_lines[j] = line;
    }
  }
}

void nps_obstacle_finish(struct nps_obstacle *o)
{
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    for (int k = 0; k < 2; k++) {
      o->lo_m[k] = o->centre_m[k] - o->radius_m;
      o->hi_m[k] = o->centre_m[k] + o->radius_m;
    }
    return;
  }
  if (nps_geometry_polygon_area2((const double (*)[2])o->corners, o->num_corners) < 0.) {
    reverse_corners(o);
  }
  o->lo_m[0] = o->lo_m[1] = INFINITY;
  o->hi_m[0] = o->hi_m[1] = -INFINITY;
  for (int i = 0; i < o->num_corners; i++) {
    for (int k = 0; k < 2; k++) {
      o->lo_m[k] = fmin(o->lo_m[k], o->corners[i][k]);
      o->hi_m[k] = fmax(o->hi_m[k], o->corners[i][k]);
    }
  }
}

int nps_obstacle_copy(struct nps_obstacle *dst, const struct nps_obstacle *src)
{
  *dst = *src;
  dst->corners = NULL;
  dst->corner_lines = NULL;
  if (src->shape != NPS_OBSTACLE_POLYGON) {
    return 0;
  }
  dst->corners = malloc((size_t)src->num_corners * sizeof * dst->corners);
  dst->corner_lines = calloc((size_t)src->num_corners, sizeof * dst->corner_lines);
  if (dst->corners == NULL || dst->corner_lines == NULL) {
    nps_obstacle_free(dst);
    return -1;
  }
  memcpy(dst->corners, src->corners, (size_t)src->num_corners * sizeof * dst->corners);
  if (src->corner_lines != NULL) {
    memcpy(dst->corner_lines, src->corner_lines, (size_t)src->num_corners * sizeof * dst->corner_lines);
  }
  return 0;
}

void nps_obstacle_free(struct nps_obstacle *o)
{
  free(o->corners);
  free(o->corner_lines);
  o->corners = NULL;
  o->corner_lines = NULL;
  o->num_corners = 0;
}

/** The point q of polygon o's outline nearest to p, on edge *edge, and its squared distance. */
static double nearest_on_outline(const struct nps_obstacle *o, const double p[2], double q[2], int *edge)
{
  double best2 = INFINITY;
  for (int i = 0; i < o->num_corners; i++) {
    double on_edge[2];
    const double d2 = nps_geometry_nearest_on_segment(p, o->corners[i], o->corners[(i + 1) % o->num_corners],
                      on_edge);
    if (d2 < best2) {
      best2 = d2;
      *edge = i;
      q[0] = on_edge[0];
      q[1] = on_edge[1];
    }
  }
  return best2;
}

double nps_obstacle_signed_dist(const struct nps_obstacle *o, const double p[2])
{
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    return hypot(p[0] - o->centre_m[0], p[1] - o->centre_m[1]) - o->radius_m;
  }
  return -nps_geometry_polygon_clearance((const double (*)[2])o->corners, o->num_corners, p);
}

/** The sides of polygon o: vertical rectangles from the floor to the top, each edge's outward normal to its right
 * (the corners run counter-clockwise). */
static double ray_sides(const struct nps_obstacle *o, const double org[3], const double d[3], double normal[3])
{
  double best = INFINITY;
  for (int i = 0; i < o->num_corners; i++) {
    const double *a = o->corners[i], *b = o->corners[(i + 1) % o->num_corners];
    const double len = hypot(b[0] - a[0], b[1] - a[1]);
    const double t_x = (b[0] - a[0]) / len, t_y = (b[1] - a[1]) / len;
    const struct nps_geometry_rect side = {
      .corner = { a[0], a[1], 0. }, .e1 = { t_x, t_y, 0. }, .len1_m = len, .e2 = { 0., 0., 1. },
      .len2_m = o->height_m, .normal = { t_y, -t_x, 0. }
    };
    const double t = nps_geometry_ray_rect(org, d, &side);
    if (t < best) {
      best = t;
      memcpy(normal, side.normal, sizeof side.normal);
    }
  }
  return best;
}

double nps_obstacle_ray(const struct nps_obstacle *o, const double org[3], const double d[3], double normal[3])
{
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    const double centre[3] = { o->centre_m[0], o->centre_m[1], 0.5 * o->height_m };
    return nps_geometry_ray_cylinder(org, d, centre, o->radius_m, 0.5 * o->height_m, normal);
  }
  double best = ray_sides(o, org, d, normal);
  if (d[2] < 0. && org[2] >= o->height_m) {   /* from above: the top */
    const double t = (o->height_m - org[2]) / d[2];
    const double at[2] = { org[0] + t * d[0], org[1] + t * d[1] };
    if (t < best && nps_geometry_point_in_polygon((const double (*)[2])o->corners, o->num_corners, at)) {
      best = t;
      normal[0] = normal[1] = 0.;
      normal[2] = 1.;
    }
  }
  return best;
}

int nps_obstacle_push_out(const struct nps_obstacle *o, double pos_m[2], double radius_m)
{
  const double reach_m = nps_obstacle_signed_dist(o, pos_m);
  if (!(reach_m < radius_m)) {
    return 0;
  }
  double from[2], out[2];   /* the outline's point nearest the body, and the way out from it */
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    memcpy(from, o->centre_m, sizeof from);
    radius_m += o->radius_m;
    out[0] = pos_m[0] - from[0];
    out[1] = pos_m[1] - from[1];
  } else {
    int edge = 0;
    nearest_on_outline(o, pos_m, from, &edge);
    out[0] = pos_m[0] - from[0];
    out[1] = pos_m[1] - from[1];
    if (reach_m < 0.) {   /* the centre is inside: out is the other way */
      out[0] = -out[0];
      out[1] = -out[1];
    }
    if (out[0] == 0. && out[1] == 0.) {   /* on the outline: the edge's outward normal */
      const double *a = o->corners[edge], *b = o->corners[(edge + 1) % o->num_corners];
      out[0] = b[1] - a[1];
      out[1] = a[0] - b[0];
    }
  }
  const double len = hypot(out[0], out[1]);
  if (len == 0.) {   /* at a circle's centre: any way out will do */
    out[0] = 1.;
    out[1] = 0.;
  } else {
    out[0] /= len;
    out[1] /= len;
  }
  pos_m[0] = from[0] + radius_m * out[0];
  pos_m[1] = from[1] + radius_m * out[1];
  return 1;
}

int nps_obstacle_outline(const struct nps_obstacle *o, double (*xy)[2], int max_points)
{
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    for (int k = 0; k < max_points; k++) {
      xy[k][0] = o->centre_m[0] + o->radius_m * cos(2. * M_PI * k / max_points);
      xy[k][1] = o->centre_m[1] + o->radius_m * sin(2. * M_PI * k / max_points);
    }
    return max_points > 0 ? max_points : 0;
  }
  const int n = o->num_corners < max_points ? o->num_corners : max_points;
  memcpy(xy, o->corners, (size_t)(n > 0 ? n : 0) * sizeof * xy);
  return o->num_corners;
}

/** Whether polygon a's edges meet polygon b's, or one lies inside the other. */
static int polygons_overlap(const struct nps_obstacle *a, const struct nps_obstacle *b)
{
  for (int i = 0; i < a->num_corners; i++) {
    for (int j = 0; j < b->num_corners; j++) {
      if (nps_geometry_segments_intersect(a->corners[i], a->corners[(i + 1) % a->num_corners], b->corners[j],
                                          b->corners[(j + 1) % b->num_corners], NULL)) {
        return 1;
      }
    }
  }
  return nps_geometry_point_in_polygon((const double (*)[2])b->corners, b->num_corners, a->corners[0]) ||
         nps_geometry_point_in_polygon((const double (*)[2])a->corners, a->num_corners, b->corners[0]);
}

int nps_obstacles_overlap(const struct nps_obstacle *a, const struct nps_obstacle *b)
{
  if (a->shape == NPS_OBSTACLE_POLYGON && b->shape == NPS_OBSTACLE_POLYGON) {
    return polygons_overlap(a, b);
  }
  const struct nps_obstacle *circle = a->shape == NPS_OBSTACLE_CIRCLE ? a : b, *other = circle == a ? b : a;
  return nps_obstacle_signed_dist(other, circle->centre_m) <= circle->radius_m;
}
