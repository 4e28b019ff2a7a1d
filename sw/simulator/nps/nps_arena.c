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
 * @file nps_arena.c
 * Arena configuration defaults, construction from a configuration, and the copters of each step.
 */

#include "nps_arena.h"
#include "nps_arena_grid.h"
#include "nps_arena_params.h"
#include "nps_geometry.h"
#include "nps_walls.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void nps_wall_params_default(struct nps_wall_params *p)
{
  memset(p, 0, sizeof * p);
  /* report section 2.4.2: recommended values (numSegments 15-20: the upper end) */
  p->num_segments = 20;
  p->segment_mass_kg = 40.;
  p->joint_force_nm = 15.;
  p->threshold_m = 1.;
  p->friction_nm = 3.;
  p->max_amplitude_deg = 30.;
  p->pid_p = 1.;
  p->pid_i = 2.;
  p->pid_d = 1.;
  /* ours (docs/arena-and-walls.md, units table): a plate from the floor to 1 m, 0.4 m above the
   * flight height; a restoring weight the motor can hold at the law's largest target (3 kg: 14.7 N m
   * x sin 33 deg = 8 N m < jointForce) that still returns a free plate within seconds against friction */
  p->hinge_height_m = 1.0;
  p->curtain_mass_kg = 3.0;
  p->friction_velocity_rad_s = 0.15;
}

void nps_arena_config_init(struct nps_arena_config *cfg, const char *source)
{
  memset(cfg, 0, sizeof * cfg);
  snprintf(cfg->source, sizeof cfg->source, "%s", source ? source : "arena");
  snprintf(cfg->name, sizeof cfg->name, "arena");
  cfg->flight_height_m = 0.6;        /* report section 2.1: FINken fly at 60 cm */
  cfg->wall_height_m = 2.0;          /* estimate of the SwarmLab curtain height */
  cfg->copter_radius_m = 0.2;        /* FINken with propeller guard, ~0.4 m across (estimate) */
  cfg->copter_height_m = 0.15;       /* FINken frame with sonar boards and guard (estimate) */
  cfg->sonar_half_angle_deg = 15.;   /* HC-SR04-class ultrasonic rangers: ~15 deg effectual angle */
  cfg->sonar_range_m = 3.0;          /* report section 3.2: readings are clamped to [0.2, 3.0] m */
  cfg->sonar_offset_m = 0.;          /* sonars measured from the copter centre (set from the airframe) */
  nps_floor_init(&cfg->floor);       /* a hard floor everywhere, as the SwarmLab's */
}

static void free_obstacles(struct nps_obstacle **obstacles, int *n)
{
  for (int i = 0; i < *n; i++) {
    nps_obstacle_free(&(*obstacles)[i]);
  }
  free(*obstacles);
  *obstacles = NULL;
  *n = 0;
}

void nps_arena_config_free(struct nps_arena_config *cfg)
{
  free(cfg->points);
  free(cfg->walls);
  cfg->points = NULL;
  cfg->walls = NULL;
  cfg->num_points = 0;
  nps_floor_free(&cfg->floor);
  free_obstacles(&cfg->obstacles, &cfg->num_obstacles);
}

int nps_arena_config_rectangle(struct nps_arena_config *cfg, double width_m, double depth_m,
                               int segments_per_wall, char *err, size_t err_len)
{
  struct nps_arena_point *pts = calloc(5, sizeof * pts);
  struct nps_wall_params *walls = calloc(4, sizeof * walls);
  if (!pts || !walls) {
    free(pts);
    free(walls);
    nps_arena_errf(err, err_len, cfg->source, 0, "out of memory");
    return -1;
  }
  const double xy[5][2] = { { 0., 0. }, { width_m, 0. }, { width_m, depth_m }, { 0., depth_m }, { 0., 0. } };
  for (int i = 0; i < 5; i++) {
    pts[i].x_m = xy[i][0];
    pts[i].y_m = xy[i][1];
  }
  for (int i = 0; i < 4; i++) {
    nps_wall_params_default(&walls[i]);
    walls[i].num_segments = segments_per_wall;
  }
  free(cfg->points);
  free(cfg->walls);
  cfg->points = pts;
  cfg->walls = walls;
  cfg->num_points = 5;
  return 0;
}

int nps_arena_config_scale(struct nps_arena_config *cfg, double factor, char *err, size_t err_len)
{
  if (!(factor > 0.) || !isfinite(factor)) {
    nps_arena_errf(err, err_len, cfg->source, 0, "scale factor %g: expected a finite number > 0", factor);
    return -1;
  }
  for (int i = 0; i < cfg->num_points; i++) {
    cfg->points[i].x_m *= factor;
    cfg->points[i].y_m *= factor;
  }
  for (int i = 0; i < cfg->num_points - 1; i++) {
    cfg->walls[i].wall_width_m *= factor;
  }
  for (int i = 0; i < cfg->num_obstacles; i++) {
    struct nps_obstacle *o = &cfg->obstacles[i];
    o->centre_m[0] *= factor;
    o->centre_m[1] *= factor;
    o->radius_m *= factor;
    for (int k = 0; k < o->num_corners; k++) {
      o->corners[k][0] *= factor;
      o->corners[k][1] *= factor;
    }
  }
  return 0;
}

/** Walls and their segments from the checked polygon; the inward normal from the orientation. */
static int make_walls(struct nps_arena *a, const struct nps_arena_config *cfg)
{
  int m = cfg->num_points - 1;
  double (*pts)[2] = nps_arena_corners(cfg);
  if (!pts) {
    return -1;
  }
  double side = nps_geometry_polygon_area2((const double (*)[2])pts, m) > 0. ? 1. : -1.; /* CCW: inside on the left */
  free(pts);
  a->walls = calloc((size_t)m, sizeof * a->walls);
  if (!a->walls) {
    return -1;
  }
  a->num_walls = m;
  for (int i = 0; i < m; i++) {
    struct nps_wall *w = &a->walls[i];
    w->a[0] = cfg->points[i].x_m;
    w->a[1] = cfg->points[i].y_m;
    w->b[0] = cfg->points[i + 1].x_m;
    w->b[1] = cfg->points[i + 1].y_m;
    w->length_m = hypot(w->b[0] - w->a[0], w->b[1] - w->a[1]);
    w->t[0] = (w->b[0] - w->a[0]) / w->length_m;
    w->t[1] = (w->b[1] - w->a[1]) / w->length_m;
    w->n[0] = -side * w->t[1];
    w->n[1] = side * w->t[0];
    w->p = cfg->walls[i];
    w->plates_per_m = w->p.num_segments / w->length_m;
    w->inertia_kgm2 = nps_walls_inertia_kgm2(&w->p);
    w->restore_nm = nps_walls_restore_nm(&w->p);
    w->substep_s = nps_walls_substep_s(&w->p);
    w->first_segment = a->num_segments;
    a->num_segments += w->p.num_segments;
  }
  a->segs = calloc((size_t)a->num_segments, sizeof * a->segs);
  a->active_segs = malloc((size_t)a->num_segments * sizeof * a->active_segs);
  if (!a->segs || !a->active_segs) {
    return -1;
  }
  for (int i = 0; i < m; i++) {
    const struct nps_wall *w = &a->walls[i];
    int ns = w->p.num_segments;
    for (int k = 0; k < ns; k++) {
      struct nps_wall_segment *s = &a->segs[w->first_segment + k];
      double f0 = (double)k / ns, f1 = (double)(k + 1) / ns;
      for (int c = 0; c < 2; c++) {
        s->a[c] = w->a[c] + f0 * (w->b[c] - w->a[c]);
        s->b[c] = k + 1 == ns ? w->b[c] : w->a[c] + f1 * (w->b[c] - w->a[c]);
      }
      s->length_m = hypot(s->b[0] - s->a[0], s->b[1] - s->a[1]);
      s->wall = i;
      s->index = k;
      s->nearest_m = INFINITY;
      s->nearest_copter = -1;
      s->limit_rad = M_PI / 2.;
    }
  }
  return 0;
}

/** The configuration's obstacles, copied and finished (counter-clockwise, boxed). */
static int copy_obstacles(struct nps_arena *a, const struct nps_arena_config *cfg)
{
  if (cfg->num_obstacles == 0) {
    return 0;
  }
  a->obstacles = calloc((size_t)cfg->num_obstacles, sizeof * a->obstacles);
  if (!a->obstacles) {
    return -1;
  }
  for (; a->num_obstacles < cfg->num_obstacles; a->num_obstacles++) {
    struct nps_obstacle *o = &a->obstacles[a->num_obstacles];
    if (nps_obstacle_copy(o, &cfg->obstacles[a->num_obstacles]) != 0) {
      return -1;
    }
    nps_obstacle_finish(o);
  }
  return 0;
}

struct nps_arena *nps_arena_build(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  if (nps_arena_config_check(cfg, err, err_len) != 0) {
    return NULL;
  }
  struct nps_arena *a = calloc(1, sizeof * a);
  if (!a || make_walls(a, cfg) != 0 || copy_obstacles(a, cfg) != 0 || !(a->grid = nps_arena_grid_new(a)) ||
      nps_floor_copy(&a->floor, &cfg->floor) != 0) {
    nps_arena_free(a);
    nps_arena_errf(err, err_len, cfg->source, 0, "out of memory building the arena");
    return NULL;
  }
  snprintf(a->name, sizeof a->name, "%s", cfg->name);
  a->flight_height_m = cfg->flight_height_m;
  a->wall_height_m = cfg->wall_height_m;
  a->copter_radius_m = cfg->copter_radius_m;
  a->copter_height_m = cfg->copter_height_m;
  a->sonar_half_angle_rad = cfg->sonar_half_angle_deg * M_PI / 180.;
  a->sonar_cos_half_angle = cos(a->sonar_half_angle_rad);
  a->sonar_range_m = cfg->sonar_range_m;
  a->sonar_offset_m = cfg->sonar_offset_m;
  return a;
}

struct nps_arena *nps_arena_load(const char *path, char *err, size_t err_len)
{
  struct nps_arena_config cfg;
  if (nps_arena_config_load(&cfg, path, err, err_len) != 0) {
    return NULL;
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, err_len);
  nps_arena_config_free(&cfg);
  return a;
}

struct nps_arena *nps_arena_new_rectangle(double width_m, double depth_m, int segments_per_wall,
                                          char *err, size_t err_len)
{
  struct nps_arena_config cfg;
  char source[96];
  snprintf(source, sizeof source, "rectangle %g m x %g m", width_m, depth_m);
  nps_arena_config_init(&cfg, source);
  if (nps_arena_config_rectangle(&cfg, width_m, depth_m, segments_per_wall, err, err_len) != 0) {
    return NULL;
  }
  struct nps_arena *a = nps_arena_build(&cfg, err, err_len);
  nps_arena_config_free(&cfg);
  return a;
}

void nps_arena_free(struct nps_arena *a)
{
  if (!a) {
    return;
  }
  nps_arena_grid_free(a->grid);
  nps_floor_free(&a->floor);
  free_obstacles(&a->obstacles, &a->num_obstacles);
  free(a->walls);
  free(a->segs);
  free(a->active_segs);
  free(a->copters);
  free(a);
}

struct nps_arena_copter nps_arena_copter_make(const struct nps_arena *a, int id, double x_m, double y_m,
                                              double z_m, double yaw_rad)
{
  struct nps_arena_copter c = {
    .id = id, .pos_m = { x_m, y_m, z_m }, .yaw_rad = yaw_rad,
    .radius_m = a->copter_radius_m, .height_m = a->copter_height_m
  };
  nps_arena_copter_refresh_yaw_trig(&c);
  return c;
}

void nps_arena_copter_recompute_yaw_trig(struct nps_arena_copter *c)
{
  const double turn_rad = c->yaw_rad - c->base_yaw_rad;
  if (c->yaw_trig_valid && fabs(turn_rad) <= NPS_ARENA_YAW_TRIG_TURN_MAX_RAD) {
    /* the base turned by the angle-addition formula (nps_arena.h); 1 - cos d and sin d summed as small terms */
    const double one_minus_cos = 0.5 * turn_rad * turn_rad, sin_turn = turn_rad - turn_rad * one_minus_cos * (1.0 / 3.0);
    c->cos_yaw = c->cos_base - (c->cos_base * one_minus_cos + c->sin_base * sin_turn);
    c->sin_yaw = c->sin_base + (c->cos_base * sin_turn - c->sin_base * one_minus_cos);
  } else {
    c->base_yaw_rad = c->yaw_rad;
    c->cos_yaw = c->cos_base = cos(c->yaw_rad);
    c->sin_yaw = c->sin_base = sin(c->yaw_rad);
  }
  c->trig_yaw_rad = c->yaw_rad;
  c->yaw_trig_valid = 1;
}

/** Refresh the yaw memo of the arena's copters (a copter whose yaw did not change costs a comparison). */
static void refresh_yaw_trig(struct nps_arena *a)
{
  for (int i = 0; i < a->num_copters; i++) {
    nps_arena_copter_refresh_yaw_trig(&a->copters[i]);
  }
}

/** Finite poses: centres and yaws. */
static int poses_finite(const struct nps_arena_copter *copters, int n)
{
  for (int i = 0; i < n; i++) {
    const struct nps_arena_copter *c = &copters[i];
    if (!isfinite(c->pos_m[0]) || !isfinite(c->pos_m[1]) || !isfinite(c->pos_m[2]) || !isfinite(c->yaw_rad)) {
      return 0;
    }
  }
  return 1;
}

/** Ids >= 0, finite poses, positive finite sizes. */
static int copters_valid(const struct nps_arena_copter *copters, int n)
{
  for (int i = 0; i < n; i++) {
    const struct nps_arena_copter *c = &copters[i];
    if (c->id < 0 || !(c->radius_m > 0.) || !(c->height_m > 0.) || !isfinite(c->radius_m) || !isfinite(c->height_m)) {
      return 0;
    }
  }
  return poses_finite(copters, n);
}

/** Rebuild the copter index; on ENOMEM the arena is left with no copters. */
static int index_copters(struct nps_arena *a)
{
  if (nps_arena_grid_set_copters(a->grid, a->copters, a->num_copters) != 0) {
    a->num_copters = 0;
    nps_arena_grid_set_copters(a->grid, a->copters, 0); /* needs no memory: empties the index */
    errno = ENOMEM;
    return -1;
  }
  return 0;
}

int nps_arena_set_copters(struct nps_arena *a, const struct nps_arena_copter *copters, int n)
{
  if (n < 0 || (n > 0 && !copters) || !copters_valid(copters, n)) {
    errno = EINVAL;
    return -1;
  }
  if (n > a->copters_capacity) {
    struct nps_arena_copter *p = realloc(a->copters, (size_t)n * sizeof * p);
    if (!p) {
      errno = ENOMEM;
      return -1;
    }
    a->copters = p;
    a->copters_capacity = n;
  }
  if (n > 0) {
    memcpy(a->copters, copters, (size_t)n * sizeof * copters);
  }
  a->num_copters = n;
  refresh_yaw_trig(a);
  return index_copters(a);
}

int nps_arena_poses_moved(struct nps_arena *a)
{
  /* one pass: a copter's yaw memo is refreshed once its pose is known finite (refreshing the memo of the copters
   * before a bad one changes nothing they show: it is of their own yaw) */
  for (int i = 0; i < a->num_copters; i++) {
    struct nps_arena_copter *c = &a->copters[i];
    if (!poses_finite(c, 1)) {
      errno = EINVAL;
      return -1;
    }
    nps_arena_copter_refresh_yaw_trig(c);
  }
  return index_copters(a);
}

int nps_arena_obstacle_outline(const struct nps_arena *a, int i, double *xy, int max_points, double *height_m)
{
  if (i < 0 || i >= a->num_obstacles) {
    return -1;
  }
  *height_m = a->obstacles[i].height_m;
  return nps_obstacle_outline(&a->obstacles[i], (double (*)[2])xy, max_points);
}

int nps_arena_obstacle_circle(const struct nps_arena *a, int i, double circle[3])
{
  if (i < 0 || i >= a->num_obstacles) {
    return -1;
  }
  const struct nps_obstacle *o = &a->obstacles[i];
  if (o->shape != NPS_OBSTACLE_CIRCLE) {
    return 0;
  }
  circle[0] = o->centre_m[0];
  circle[1] = o->centre_m[1];
  circle[2] = o->radius_m;
  return 1;
}

int nps_arena_copter_index(const struct nps_arena *a, int id)
{
  for (int i = 0; i < a->num_copters; i++) {
    if (a->copters[i].id == id) {
      return i;
    }
  }
  return -1;
}
