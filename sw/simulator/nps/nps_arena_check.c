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
 * @file nps_arena_check.c
 * Checks of an arena configuration, with errors naming the source, the line and the value: the polygon
 * is closed and simple, every parameter is in range, each given wallWidth matches its edge, the plates can be
 * simulated (not too many, integration steps not too short), a copter fits in the arena (vertically between
 * floor and wall top, horizontally inside the polygon), and the floor's regions are known materials, inside the
 * polygon and do not overlap.
 */

#include "nps_arena.h"
#include "nps_arena_params.h"
#include "nps_geometry.h"
#include "nps_walls.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/** A given wallWidth may differ from its polygon edge by this much [m] (1 mm: drawing precision). */
#define WALL_WIDTH_TOL_M 1e-3
/** Accuracy of the inscribed-circle search behind the "copter cannot fit" check [m]. */
#define FIT_TOL_M 1e-4
/** Most plates of all walls together (make bench's largest arenas have 4000; each costs ~0.2 kB). */
#define MAX_PLATES 100000

double (*nps_arena_corners(const struct nps_arena_config *cfg))[2]
{
  int m = cfg->num_points - 1;
  double (*pts)[2] = malloc((size_t)(m > 0 ? m : 1) * sizeof * pts);
  for (int i = 0; pts && i < m; i++) {
    pts[i][0] = cfg->points[i].x_m;
    pts[i][1] = cfg->points[i].y_m;
  }
  return pts;
}

/** The polygon's corners (nps_arena_corners), or NULL with "out of memory" in err. */
static double (*corners_or_fail(const struct nps_arena_config *cfg, char *err, size_t err_len))[2]
{
  double (*pts)[2] = nps_arena_corners(cfg);
  if (!pts) {
    nps_arena_errf(err, err_len, cfg->source, 0, "out of memory");
  }
  return pts;
}

static int point_line(const struct nps_arena_config *cfg, int i)
{
  return cfg->points[i].line > 0 ? cfg->points[i].line : cfg->polygon_line;
}

/** One closed outline to check: m corners (not repeating the first), each with its line (0: the outline's). */
struct outline {
  const char *source;
  const char *edge;         /**< what an edge is called in messages: "wall", "edge" */
  const double (*pts)[2];
  const int *lines;         /**< num_lines lines: of corner i, then of the repeated first corner if given */
  int num_lines;
  int m;
  int line;                 /**< line of the outline's element */
};

static int corner_line(const struct outline *o, int i)
{
  const int line = o->lines == NULL ? 0 : o->lines[i < o->num_lines ? i : i % o->m];
  return line > 0 ? line : o->line;
}

/** Corners finite and distinct from their neighbours, edges meeting only their neighbours at their shared corner. */
static int check_outline(const struct outline *o, char *err, size_t err_len)
{
  for (int i = 0; i < o->m; i++) {
    if (!isfinite(o->pts[i][0]) || !isfinite(o->pts[i][1])) {
      nps_arena_errf(err, err_len, o->source, corner_line(o, i), "point %d is not finite", i);
      return -1;
    }
  }
  for (int i = 1; i <= o->m; i++) {
    const double *p = o->pts[i % o->m], *prev = o->pts[i - 1];
    if (p[0] == prev[0] && p[1] == prev[1]) {
      nps_arena_errf(err, err_len, o->source, corner_line(o, i),
                     "point (%g, %g) repeats the previous point: a %s of length 0", p[0], p[1], o->edge);
      return -1;
    }
  }
  for (int i = 0; i < o->m; i++) {
    const double *p1 = o->pts[i], *p2 = o->pts[(i + 1) % o->m];
    for (int j = i + 1; j < o->m; j++) {
      const double *q1 = o->pts[j], *q2 = o->pts[(j + 1) % o->m];
      int adjacent = (j == i + 1) || (i == 0 && j == o->m - 1);
      double at[2] = { 0., 0. };
      int bad;
      if (adjacent) {
        /* neighbours share one corner; they overlap only if they fold back on each other */
        const double *shared = (j == i + 1) ? p2 : p1;
        const double *pi = (j == i + 1) ? p1 : p2;
        const double *qj = (j == i + 1) ? q2 : q1;
        double cross = (pi[0] - shared[0]) * (qj[1] - shared[1]) - (pi[1] - shared[1]) * (qj[0] - shared[0]);
        double dot = (pi[0] - shared[0]) * (qj[0] - shared[0]) + (pi[1] - shared[1]) * (qj[1] - shared[1]);
        bad = cross == 0. && dot > 0.;
        at[0] = shared[0];
        at[1] = shared[1];
      } else {
        bad = nps_geometry_segments_intersect(p1, p2, q1, q2, at);
      }
      if (bad) {
        nps_arena_errf(err, err_len, o->source, corner_line(o, j),
                       "the polygon intersects itself: %s %d (from point %d) and %s %d (from point %d) meet at (%g, %g)",
                       o->edge, i, i, o->edge, j, j, at[0], at[1]);
        return -1;
      }
    }
  }
  return 0;
}

static int check_polygon(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  const char *src = cfg->source;
  int n = cfg->num_points;
  if (n < 4) {
    nps_arena_errf(err, err_len, src, cfg->polygon_line > 0 ? cfg->polygon_line : cfg->line,
                   "the polygon has %d point(s): it needs at least 3 corners and a last point repeating the first", n);
    return -1;
  }
  for (int i = 0; i < n; i++) {
    if (!isfinite(cfg->points[i].x_m) || !isfinite(cfg->points[i].y_m)) {
      nps_arena_errf(err, err_len, src, point_line(cfg, i), "point %d is not finite", i);
      return -1;
    }
  }
  const struct nps_arena_point *first = &cfg->points[0], *last = &cfg->points[n - 1];
  if (first->x_m != last->x_m || first->y_m != last->y_m) {
    nps_arena_errf(err, err_len, src, point_line(cfg, n - 1),
                   "the polygon is not closed: its last point (%g, %g) must repeat its first point (%g, %g)",
                   last->x_m, last->y_m, first->x_m, first->y_m);
    return -1;
  }
  double (*pts)[2] = nps_arena_corners(cfg);
  int *lines = malloc((size_t)n * sizeof * lines);
  for (int i = 0; lines && i < n; i++) {
    lines[i] = point_line(cfg, i);
  }
  int rc = -1;
  if (!pts || !lines) {
    nps_arena_errf(err, err_len, src, 0, "out of memory");
  } else {
    const struct outline o = { src, "wall", (const double (*)[2])pts, lines, n, n - 1, cfg->polygon_line };
    rc = check_outline(&o, err, err_len);
  }
  free(pts);
  free(lines);
  return rc;
}

static int check_walls(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  char why[256];
  for (int i = 0; i < cfg->num_points - 1; i++) {
    const struct nps_wall_params *p = &cfg->walls[i];
    int line = p->line > 0 ? p->line : cfg->line;
    if (nps_arena_param_check_all(&nps_arena_wall_table, p, why, sizeof why) != 0) {
      nps_arena_errf(err, err_len, cfg->source, line, "wall %d: %s", i, why);
      return -1;
    }
    double dx = cfg->points[i + 1].x_m - cfg->points[i].x_m;
    double dy = cfg->points[i + 1].y_m - cfg->points[i].y_m;
    double len = hypot(dx, dy);
    if (p->wall_width_m != 0. && fabs(p->wall_width_m - len) > WALL_WIDTH_TOL_M) {
      nps_arena_errf(err, err_len, cfg->source, line,
                     "wall %d: wallWidth = %g m but its polygon edge is %.4g m long", i, p->wall_width_m, len);
      return -1;
    }
    if (p->hinge_height_m > cfg->wall_height_m) {
      nps_arena_errf(err, err_len, cfg->source, line,
                     "wall %d: hingeHeight = %g m is above the wall height %g m", i, p->hinge_height_m, cfg->wall_height_m);
      return -1;
    }
  }
  return 0;
}

/** The plates can be simulated: not too many, and each wall's within NPS_WALLS_MIN_SUBSTEP_S. */
static int check_plates(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  long long plates = 0;
  for (int i = 0; i < cfg->num_points - 1; i++) {
    const struct nps_wall_params *p = &cfg->walls[i];
    const int line = p->line > 0 ? p->line : cfg->line;
    plates += p->num_segments;
    if (plates > MAX_PLATES) {
      nps_arena_errf(err, err_len, cfg->source, line, "wall %d: numSegments = %d makes more than %d plates in all",
                     i, p->num_segments, MAX_PLATES);
      return -1;
    }
    if (!isfinite(nps_walls_inertia_kgm2(p)) || !isfinite(nps_walls_restore_nm(p))) {
      nps_arena_errf(err, err_len, cfg->source, line, "wall %d: segmentMass = %g kg or curtainMass = %g kg is too "
                     "heavy to simulate", i, p->segment_mass_kg, p->curtain_mass_kg);
      return -1;
    }
    const double substep_s = nps_walls_substep_s(p);
    if (!(substep_s >= NPS_WALLS_MIN_SUBSTEP_S)) {
      nps_arena_errf(err, err_len, cfg->source, line, "wall %d: its plates would need integration steps of %.3g s, "
                     "shorter than %g s: lower PID_P, PID_D, friction or curtainMass, or raise segmentMass, "
                     "hingeHeight or frictionVelocity", i, substep_s, NPS_WALLS_MIN_SUBSTEP_S);
      return -1;
    }
  }
  return 0;
}

static int region_line(const struct nps_arena_config *cfg, const struct nps_floor_region *r)
{
  return r->line > 0 ? r->line : cfg->floor.line > 0 ? cfg->floor.line : cfg->line;
}

/** Whether the closed rectangle r lies in the polygon: no edge passes through its inside, and its centre is in. */
static bool region_inside(const double (*pts)[2], int m, const struct nps_floor_region *r)
{
  const double lo[2] = { r->x0_m, r->y0_m }, hi[2] = { r->x1_m, r->y1_m };
  for (int i = 0; i < m; i++) {
    if (nps_geometry_segment_enters_box(pts[i], pts[(i + 1) % m], lo, hi)) {
      return false;
    }
  }
  const double centre[2] = { 0.5 * (r->x0_m + r->x1_m), 0.5 * (r->y0_m + r->y1_m) };
  return nps_geometry_point_in_polygon(pts, m, centre);
}

/** Every region: a known material, a rectangle of positive area inside the polygon, overlapping no other region. */
static int check_floor(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  const struct nps_floor *f = &cfg->floor;
  if (f->default_material <= NPS_FLOOR_NONE || f->default_material >= NPS_FLOOR_MATERIALS) {
    nps_arena_errf(err, err_len, cfg->source, f->line > 0 ? f->line : cfg->line,
                   "<floor> material code %d: expected a floor material (%s)", (int)f->default_material,
                   nps_floor_material_names());
    return -1;
  }
  const int m = cfg->num_points - 1;
  double (*pts)[2] = corners_or_fail(cfg, err, err_len);
  if (!pts) {
    return -1;
  }
  int rc = 0;
  for (int i = 0; rc == 0 && i < f->num_regions; i++) {
    const struct nps_floor_region *r = &f->regions[i];
    const int line = region_line(cfg, r);
    if (r->material <= NPS_FLOOR_NONE || r->material >= NPS_FLOOR_MATERIALS) {
      nps_arena_errf(err, err_len, cfg->source, line, "<region> material code %d: expected a floor material (%s)",
                     (int)r->material, nps_floor_material_names());
      rc = -1;
    } else if (!(r->x0_m < r->x1_m && r->y0_m < r->y1_m)) {
      nps_arena_errf(err, err_len, cfg->source, line, "<region> (%g, %g)-(%g, %g): expected x0 < x1 and y0 < y1 [m]",
                     r->x0_m, r->y0_m, r->x1_m, r->y1_m);
      rc = -1;
    } else if (!region_inside((const double (*)[2])pts, m, r)) {
      nps_arena_errf(err, err_len, cfg->source, line, "<region> (%g, %g)-(%g, %g) reaches outside the arena polygon",
                     r->x0_m, r->y0_m, r->x1_m, r->y1_m);
      rc = -1;
    }
    for (int j = 0; rc == 0 && j < i; j++) {
      const struct nps_floor_region *q = &f->regions[j];
      const double x0 = fmax(r->x0_m, q->x0_m), x1 = fmin(r->x1_m, q->x1_m);
      const double y0 = fmax(r->y0_m, q->y0_m), y1 = fmin(r->y1_m, q->y1_m);
      if (x0 < x1 && y0 < y1) {
        nps_arena_errf(err, err_len, cfg->source, line,
                       "<region> overlaps the <region> of line %d on (%g, %g)-(%g, %g)", region_line(cfg, q), x0, y0, x1, y1);
        rc = -1;
      }
    }
  }
  free(pts);
  return rc;
}

/** Where obstacle o lies against the arena's polygon pts (m corners): 0 inside and clear of every wall, else -1
 * with the reason. */
static int obstacle_inside(const struct nps_arena_config *cfg, const double (*pts)[2], int m,
                           const struct nps_obstacle *o, int i, char *err, size_t err_len)
{
  const double *inner = o->shape == NPS_OBSTACLE_CIRCLE ? o->centre_m : o->corners[0];
  if (!nps_geometry_point_in_polygon(pts, m, inner)) {
    nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d lies outside the arena's polygon", i);
    return -1;
  }
  for (int w = 0; w < m; w++) {
    const double *a = pts[w], *b = pts[(w + 1) % m];
    int touches = 0;
    if (o->shape == NPS_OBSTACLE_CIRCLE) {
      touches = nps_geometry_point_segment_dist2(o->centre_m, a, b) <= o->radius_m * o->radius_m;
    }
    for (int k = 0; !touches && k < o->num_corners; k++) {
      touches = nps_geometry_segments_intersect(o->corners[k], o->corners[(k + 1) % o->num_corners], a, b, NULL);
    }
    if (touches) {
      nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d overlaps wall %d (from (%g, %g) to (%g, %g)): an "
                     "obstacle stands inside the arena, clear of the walls", i, w, a[0], a[1], b[0], b[1]);
      return -1;
    }
  }
  return 0;
}

/** Obstacle i alone: its height and footprint. */
static int check_obstacle_shape(const struct nps_arena_config *cfg, const struct nps_obstacle *o, int i, char *err,
                                size_t err_len)
{
  if (!(o->height_m > 0.)) {
    nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d: height %g m: expected a height > 0 m", i,
                   o->height_m);
    return -1;
  }
  if (o->shape == NPS_OBSTACLE_CIRCLE) {
    if (!isfinite(o->centre_m[0]) || !isfinite(o->centre_m[1]) || !(o->radius_m > 0.)) {
      nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d: a circle needs a finite centre and a radius "
                     "> 0 m (radius %g m)", i, o->radius_m);
      return -1;
    }
    return 0;
  }
  if (o->num_corners < 3) {
    nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d: its polygon has %d corner(s): it needs at least 3",
                   i, o->num_corners);
    return -1;
  }
  const struct outline outline = { cfg->source, "edge", (const double (*)[2])o->corners, o->corner_lines,
                                   o->corner_lines != NULL ? o->num_corners : 0, o->num_corners, o->line };
  return check_outline(&outline, err, err_len);
}

/** Every obstacle: a sound footprint, inside the arena clear of the walls, clear of every other obstacle. */
static int check_obstacles(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  if (cfg->num_obstacles == 0) {
    return 0;
  }
  double (*pts)[2] = corners_or_fail(cfg, err, err_len);
  if (!pts) {
    return -1;
  }
  int rc = 0;
  for (int i = 0; rc == 0 && i < cfg->num_obstacles; i++) {
    const struct nps_obstacle *o = &cfg->obstacles[i];
    rc = check_obstacle_shape(cfg, o, i, err, err_len) != 0 ||
         obstacle_inside(cfg, (const double (*)[2])pts, cfg->num_points - 1, o, i, err, err_len) != 0 ? -1 : 0;
    for (int j = 0; rc == 0 && j < i; j++) {
      if (nps_obstacles_overlap(o, &cfg->obstacles[j])) {
        nps_arena_errf(err, err_len, cfg->source, o->line, "obstacle %d overlaps obstacle %d (line %d)", i, j,
                       cfg->obstacles[j].line);
        rc = -1;
      }
    }
  }
  free(pts);
  return rc;
}

bool nps_arena_height_fits(double copter_height_m, double wall_height_m, double z_m)
{
  const double half = 0.5 * copter_height_m;
  return z_m - half > 0. && z_m + half <= wall_height_m;
}

static int check_fit(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  if (!nps_arena_height_fits(cfg->copter_height_m, cfg->wall_height_m, cfg->flight_height_m)) {
    nps_arena_errf(err, err_len, cfg->source, cfg->line,
                   "a copter %g m tall at flightHeight %g m does not fit between the floor and the wall top at %g m",
                   cfg->copter_height_m, cfg->flight_height_m, cfg->wall_height_m);
    return -1;
  }
  int m = cfg->num_points - 1;
  double (*pts)[2] = corners_or_fail(cfg, err, err_len);
  if (!pts) {
    return -1;
  }
  double clear = nps_geometry_polygon_max_clearance((const double (*)[2])pts, m, FIT_TOL_M, cfg->copter_radius_m);
  free(pts);
  if (clear < cfg->copter_radius_m) {
    nps_arena_errf(err, err_len, cfg->source, cfg->polygon_line > 0 ? cfg->polygon_line : cfg->line,
                   "a copter of radius %g m cannot fit in the polygon: its largest inscribed circle has radius %.4g m",
                   cfg->copter_radius_m, clear);
    return -1;
  }
  return 0;
}

int nps_arena_config_check(const struct nps_arena_config *cfg, char *err, size_t err_len)
{
  char why[256];
  const struct nps_arena_param_table *tables[] = {
    &nps_arena_arena_table, &nps_arena_copters_table, &nps_arena_sonars_table
  };
  const int lines[] = { cfg->line, cfg->copters_line, cfg->sonars_line };
  for (int k = 0; k < 3; k++) {
    if (nps_arena_param_check_all(tables[k], cfg, why, sizeof why) != 0) {
      nps_arena_errf(err, err_len, cfg->source, lines[k] > 0 ? lines[k] : cfg->line, "<%s> %s",
                     tables[k]->element, why);
      return -1;
    }
  }
  if (check_polygon(cfg, err, err_len) != 0 || check_walls(cfg, err, err_len) != 0 ||
      check_plates(cfg, err, err_len) != 0 || check_fit(cfg, err, err_len) != 0 ||
      check_floor(cfg, err, err_len) != 0 || check_obstacles(cfg, err, err_len) != 0) {
    return -1;
  }
  return 0;
}
