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
 * @file nps_arena_grid.c
 * Uniform grid over the arena (see nps_arena_grid.h).
 */

#include "nps_arena_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int clamp_index(double v, int n)
{
  if (!(v >= 0.)) {
    return 0;
  }
  if (v >= (double)(n - 1)) {
    return n - 1;
  }
  return (int)v;
}

/** nps_arena_grid_box, inlined where the copters are indexed (every copter, every step). */
static inline int box_cells(const struct nps_arena_grid *g, double xlo, double ylo, double xhi, double yhi,
                            int *ix0, int *iy0, int *ix1, int *iy1)
{
  double fx0 = (xlo - g->x0_m) * g->inv_cell, fx1 = (xhi - g->x0_m) * g->inv_cell;
  double fy0 = (ylo - g->y0_m) * g->inv_cell, fy1 = (yhi - g->y0_m) * g->inv_cell;
  if (!(fx1 >= 0. && fy1 >= 0. && fx0 <= g->nx && fy0 <= g->ny)) {
    return 0;
  }
  *ix0 = clamp_index(fx0, g->nx);
  *ix1 = clamp_index(fx1, g->nx);
  *iy0 = clamp_index(fy0, g->ny);
  *iy1 = clamp_index(fy1, g->ny);
  return 1;
}

int nps_arena_grid_box(const struct nps_arena_grid *g, double xlo, double ylo, double xhi, double yhi,
                       int *ix0, int *iy0, int *ix1, int *iy1)
{
  return box_cells(g, xlo, ylo, xhi, yhi, ix0, iy0, ix1, iy1);
}

/** nps_arena_grid_cell, inlined where the copters are indexed. */
static inline int cell_of(const struct nps_arena_grid *g, double x_m, double y_m)
{
  double fx = (x_m - g->x0_m) * g->inv_cell, fy = (y_m - g->y0_m) * g->inv_cell;
  if (!(fx >= 0. && fy >= 0. && fx < g->nx && fy < g->ny)) {
    return -1;
  }
  return (int)fy * g->nx + (int)fx;
}

int nps_arena_grid_cell(const struct nps_arena_grid *g, double x_m, double y_m)
{
  return cell_of(g, x_m, y_m);
}

/** Fill a CSR from per-cell counts in g->scratch: start[] gets the offsets, scratch becomes fill cursors. */
static void counts_to_starts(struct nps_arena_grid *g, int *start)
{
  int cells = g->nx * g->ny, sum = 0;
  for (int c = 0; c < cells; c++) {
    start[c] = sum;
    sum += g->scratch[c];
    g->scratch[c] = start[c];
  }
  start[cells] = sum;
}

/**
 * CSR of items by box: item i goes to every cell its box[i] = {xlo, ylo, xhi, yhi} overlaps.
 * @return 0, or -1 on ENOMEM
 */
static int index_boxes(struct nps_arena_grid *g, int n, const double (*box)[4], int *start, int **items)
{
  int cells = g->nx * g->ny;
  memset(g->scratch, 0, (size_t)cells * sizeof * g->scratch);
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < n; i++) {
      int b[4];
      const double pad = NPS_ARENA_GRID_PAD_M;
      if (!nps_arena_grid_box(g, box[i][0] - pad, box[i][1] - pad, box[i][2] + pad, box[i][3] + pad,
                              &b[0], &b[1], &b[2], &b[3])) {
        continue;
      }
      for (int iy = b[1]; iy <= b[3]; iy++) {
        for (int ix = b[0]; ix <= b[2]; ix++) {
          int c = iy * g->nx + ix;
          if (pass == 0) {
            g->scratch[c]++;
          } else {
            (*items)[g->scratch[c]++] = i;
          }
        }
      }
    }
    if (pass == 0) {
      counts_to_starts(g, start);
      *items = malloc((size_t)(start[cells] > 0 ? start[cells] : 1) * sizeof ** items);
      if (!*items) {
        return -1;
      }
    }
  }
  return 0;
}

/** Boxes of the walls, grown by their threshold (the copters a wall feels) and by their hinge height (where
 * its plates can be: the bottom edge of a plate swings at most L inward). */
static int index_arena(struct nps_arena_grid *g, const struct nps_arena *a)
{
  double (*box)[4] = malloc((size_t)a->num_walls * sizeof * box);
  if (!box) {
    return -1;
  }
  int rc = 0;
  for (int pass = 0; rc == 0 && pass < 2; pass++) {
    for (int i = 0; i < a->num_walls; i++) {
      const struct nps_wall *w = &a->walls[i];
      double r = pass == 0 ? w->p.threshold_m : w->p.hinge_height_m;
      box[i][0] = fmin(w->a[0], w->b[0]) - r;
      box[i][1] = fmin(w->a[1], w->b[1]) - r;
      box[i][2] = fmax(w->a[0], w->b[0]) + r;
      box[i][3] = fmax(w->a[1], w->b[1]) + r;
    }
    rc = pass == 0 ? index_boxes(g, a->num_walls, (const double (*)[4])box, g->wall_start, &g->wall_items)
         : index_boxes(g, a->num_walls, (const double (*)[4])box, g->reach_start, &g->reach_items);
  }
  free(box);
  return rc;
}

/** Rounding margin [m] of wall_clear: far above the rounding of the wall coordinates of any arena. */
#define WALL_CLEAR_TOL_M 1e-9

/**
 * How far inside wall w every point of the rectangle [x0, x1] x [y0, y1] surely is, as the contacts test it
 * (nps_arena_contact.c: a copter is pushed when along the wall in [0, length] and inward closer than its
 * radius): INFINITY when every point is surely beyond one end of the wall, else the least inward distance
 * of the corners (both are linear, so a rectangle's extremes are at its corners), less the margin.
 */
static double rect_wall_clear(const struct nps_wall *w, double x0, double y0, double x1, double y1)
{
  const double xs[2] = { x0, x1 }, ys[2] = { y0, y1 };
  double along_lo = INFINITY, along_hi = -INFINITY, inside_lo = INFINITY;
  for (int k = 0; k < 4; k++) {
    const double rx = xs[k & 1] - w->a[0], ry = ys[k >> 1] - w->a[1];
    along_lo = fmin(along_lo, rx * w->t[0] + ry * w->t[1]);
    along_hi = fmax(along_hi, rx * w->t[0] + ry * w->t[1]);
    inside_lo = fmin(inside_lo, rx * w->n[0] + ry * w->n[1]);
  }
  if (along_hi < -WALL_CLEAR_TOL_M || along_lo > w->length_m + WALL_CLEAR_TOL_M) {
    return INFINITY;
  }
  return inside_lo - WALL_CLEAR_TOL_M;
}

/**
 * The least distance from a point of the cell [x0, x1] x [y0, y1] to obstacle o's bounding box, less the margin: no
 * body closer to the box than its radius reaches the obstacle (nps_arena_contact.c pushes one that does).
 */
static double rect_box_clear(const struct nps_obstacle *o, double x0, double y0, double x1, double y1)
{
  const double gap_x = fmax(0., fmax(o->lo_m[0] - x1, x0 - o->hi_m[0]));
  const double gap_y = fmax(0., fmax(o->lo_m[1] - y1, y0 - o->hi_m[1]));
  return hypot(gap_x, gap_y) - WALL_CLEAR_TOL_M;
}

/** wall_clear_m of every cell (the least over the walls): cells x walls work, done only for a few walls. */
static void index_wall_clear(struct nps_arena_grid *g, const struct nps_arena *a)
{
  for (int iy = 0; iy < g->ny; iy++) {
    for (int ix = 0; ix < g->nx; ix++) {
      const double x0 = g->x0_m + ix * g->cell_m, y0 = g->y0_m + iy * g->cell_m;
      double clear = a->num_walls <= g->direct_max_walls ? INFINITY : -INFINITY;
      for (int w = 0; w < a->num_walls && clear > -INFINITY; w++) {
        clear = fmin(clear, rect_wall_clear(&a->walls[w], x0, y0, x0 + g->cell_m, y0 + g->cell_m));
      }
      for (int k = 0; k < a->num_obstacles && clear > -INFINITY; k++) {
        clear = fmin(clear, rect_box_clear(&a->obstacles[k], x0, y0, x0 + g->cell_m, y0 + g->cell_m));
      }
      g->wall_clear_m[iy * g->nx + ix] = clear;
    }
  }
}

/** Body box of copter c in cells and the cell of its centre; 0 (box[0] = -1) if the box leaves the grid. */
static int body_cells(const struct nps_arena_grid *g, const struct nps_arena_copter *c, int box[4], int *centre)
{
  const double r = c->radius_m + NPS_ARENA_GRID_PAD_M;
  const double xlo = c->pos_m[0] - r, xhi = c->pos_m[0] + r, ylo = c->pos_m[1] - r, yhi = c->pos_m[1] + r;
  if (!(xlo >= g->x0_m && ylo >= g->y0_m && xhi < g->x0_m + g->nx * g->cell_m && yhi < g->y0_m + g->ny * g->cell_m) ||
      !box_cells(g, xlo, ylo, xhi, yhi, &box[0], &box[1], &box[2], &box[3])) {
    box[0] = box[1] = box[2] = box[3] = -1;
    *centre = -1;
    return 0;
  }
  *centre = cell_of(g, c->pos_m[0], c->pos_m[1]);
  return 1;
}

/** An empty stay box: every centre leaves it (and a NaN one too). */
static void stay_empty(struct nps_arena_grid_stay *s)
{
  s->lo[0] = s->lo[1] = INFINITY;
  s->hi[0] = s->hi[1] = -INFINITY;
}

/**
 * The stay box of copter c (nps_arena_grid_stay) whose body box cells and centre cell body_cells just found: along
 * each axis, the centre stays within the cell of its body box's low edge (centre - r), of its high edge
 * (centre + r) and of itself, and within the grid. Margin: body_cells's cell indices are (x - r - origin) / cell
 * rounded three times, off by less than 1e-15 of the magnitudes |origin| + extent + r (a centre in the box is
 * within them); the margin is 1e-12 of them, so a centre in the box surely gets the same indices.
 */
static void stay_set(const struct nps_arena_grid *g, struct nps_arena_grid_stay *s, const struct nps_arena_copter *c,
                     const int box[4], int centre)
{
  s->radius_m = c->radius_m;
  if (centre < 0) {
    stay_empty(s);
    return;
  }
  const double r = c->radius_m + NPS_ARENA_GRID_PAD_M;   /* as body_cells */
  const double origin[2] = { g->x0_m, g->y0_m }, cell = g->cell_m;
  const int cells[2] = { g->nx, g->ny }, centre_idx[2] = { centre % g->nx, centre / g->nx };
  const double margin = 1e-12 * (fabs(g->x0_m) + fabs(g->y0_m) + (g->nx + g->ny) * cell + r);
  for (int k = 0; k < 2; k++) {
    const double o = origin[k];
    const double lo = fmax(fmax(o + r + box[k] * cell, o - r + box[k + 2] * cell), fmax(o + centre_idx[k] * cell, o + r));
    const double hi = fmin(fmin(o + r + (box[k] + 1) * cell, o - r + (box[k + 2] + 1) * cell),
                           fmin(o + (centre_idx[k] + 1) * cell, o + cells[k] * cell - r));
    s->lo[k] = lo + margin;
    s->hi[k] = hi - margin;
  }
}

/** Put item into the list of cell (items ascending). */
static void list_insert(int *head, int *next, int cell, int item)
{
  int *link = &head[cell];
  while (*link >= 0 && *link < item) {
    link = &next[*link];
  }
  next[item] = *link;
  *link = item;
}

/** Take item out of the list of cell. */
static void list_remove(int *head, int *next, int cell, int item)
{
  int *link = &head[cell];
  while (*link != item) {
    link = &next[*link];
  }
  *link = next[item];
}

/** Copter i's entries in the body lists of the cells of box, or out of them (insert 0). */
static void link_body(struct nps_arena_grid *g, int i, const int box[4], int insert)
{
  int entry = i << g->body_shift;
  for (int iy = box[1]; iy <= box[3]; iy++) {
    for (int ix = box[0]; ix <= box[2]; ix++, entry++) {
      if (insert) {
        list_insert(g->body_head, g->body_next, iy * g->nx + ix, entry);
      } else {
        list_remove(g->body_head, g->body_next, iy * g->nx + ix, entry);
      }
    }
  }
}

/** Empty every list; every copter is then not indexed. */
static void clear_copters(struct nps_arena_grid *g)
{
  const int cells = g->nx * g->ny;
  for (int c = 0; c < cells; c++) {
    g->body_head[c] = -1;
    g->centre_head[c] = -1;
  }
  for (int i = 0; i < g->num_copters; i++) {
    g->copter_box[i][0] = -2;
    g->centre_cell[i] = -1;
    stay_empty(&g->stay[i]);
    g->wall_free[i].cell = -1;
  }
  g->num_overflow = 0;
}

static int grow(void *items, int capacity, size_t item_size)
{
  void *p = realloc(*(void **)items, (size_t)(capacity > 0 ? capacity : 1) * item_size);
  if (!p) {
    return -1;
  }
  *(void **)items = p;
  return 0;
}

/** Room for n copters of up to 1 << shift body cells each, every list empty. @return 0, or -1 on ENOMEM */
static int reset_copters(struct nps_arena_grid *g, int n, int shift)
{
  g->num_copters = 0;
  clear_copters(g);
  if (n > g->copter_capacity || shift != g->body_shift) {
    const int cap = n > g->copter_capacity ? n : g->copter_capacity;
    if (grow(&g->copter_box, cap, sizeof * g->copter_box) != 0 ||
        grow(&g->stay, cap, sizeof * g->stay) != 0 ||
        grow(&g->wall_free, cap, sizeof * g->wall_free) != 0 ||
        grow(&g->centre_next, cap, sizeof * g->centre_next) != 0 ||
        grow(&g->centre_cell, cap, sizeof * g->centre_cell) != 0 ||
        grow(&g->overflow, cap, sizeof * g->overflow) != 0 ||
        grow(&g->by_cell, cap, sizeof * g->by_cell) != 0 ||
        grow(&g->by_cell_xy, cap, sizeof * g->by_cell_xy) != 0 ||
        grow(&g->body_next, cap << shift, sizeof * g->body_next) != 0) {
      return -1;   /* the index stays empty */
    }
    g->copter_capacity = cap;
    g->body_shift = shift;
  }
  g->num_copters = n;
  clear_copters(g);
  for (int i = 0; i < n; i++) {
    g->by_cell[i] = i;
    g->by_cell_xy[i][0] = g->by_cell_xy[i][1] = -1;
  }
  g->num_no_cell = n;
  return 0;
}

/** Sort by_cell again after centres changed cells (insertion sort: the old order is nearly right). */
static void sort_by_cell(struct nps_arena_grid *g)
{
  for (int k = 1; k < g->num_copters; k++) {
    const int i = g->by_cell[k], cell = g->centre_cell[i];
    int j = k;
    for (; j > 0; j--) {
      const int p = g->by_cell[j - 1];
      if (g->centre_cell[p] < cell || (g->centre_cell[p] == cell && p < i)) {
        break;
      }
      g->by_cell[j] = p;
    }
    g->by_cell[j] = i;
  }
  g->num_no_cell = 0;
  for (int k = 0; k < g->num_copters; k++) {   /* the division once per change, not once per query */
    const int cell = g->centre_cell[g->by_cell[k]], iy = cell >= 0 ? cell / g->nx : -1;
    g->by_cell_xy[k][0] = cell >= 0 ? cell - iy * g->nx : -1;
    g->by_cell_xy[k][1] = iy;
    g->num_no_cell += cell < 0;
  }
}

/** The copters whose body box leaves the grid, ascending. */
static void list_overflow(struct nps_arena_grid *g)
{
  g->num_overflow = 0;
  for (int i = 0; i < g->num_copters; i++) {
    if (g->copter_box[i][0] == -1) {
      g->overflow[g->num_overflow++] = i;
    }
  }
}

struct nps_arena_grid *nps_arena_grid_new(const struct nps_arena *a)
{
  double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
  double reach = 0.;
  for (int w = 0; w < a->num_walls; w++) {
    const struct nps_wall *wall = &a->walls[w];
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], fmin(wall->a[k], wall->b[k]));
      hi[k] = fmax(hi[k], fmax(wall->a[k], wall->b[k]));
    }
    reach = fmax(reach, fmax(wall->p.threshold_m, wall->p.hinge_height_m));
  }
  struct nps_arena_grid *g = calloc(1, sizeof * g);
  if (!g) {
    return NULL;
  }
  /* cells as large as the largest reach: a copter's own cell lists every wall that can feel it */
  double margin = 2. * reach;
  double w = hi[0] - lo[0] + 2. * margin, h = hi[1] - lo[1] + 2. * margin;
  g->cell_m = reach;
  double cells = ceil(w / g->cell_m) * ceil(h / g->cell_m);
  if (cells > NPS_ARENA_GRID_MAX_CELLS) {
    g->cell_m *= sqrt(cells / NPS_ARENA_GRID_MAX_CELLS) * 1.01;
  }
  g->inv_cell = 1. / g->cell_m;
  g->nx = (int)ceil(w / g->cell_m);
  g->ny = (int)ceil(h / g->cell_m);
  g->x0_m = lo[0] - margin;
  g->y0_m = lo[1] - margin;
  g->body_shift = 2; /* a body box smaller than a cell spans at most 2 x 2 cells */
  g->direct_max_copters = NPS_ARENA_GRID_DIRECT_MAX;
  g->direct_max_walls = NPS_ARENA_GRID_DIRECT_WALLS;
  size_t n1 = (size_t)(g->nx * g->ny + 1);
  g->wall_start = malloc(n1 * sizeof * g->wall_start);
  g->reach_start = malloc(n1 * sizeof * g->reach_start);
  g->body_head = malloc(n1 * sizeof * g->body_head);
  g->centre_head = malloc(n1 * sizeof * g->centre_head);
  g->scratch = malloc(n1 * sizeof * g->scratch);
  g->wall_clear_m = malloc(n1 * sizeof * g->wall_clear_m);
  if (!g->wall_start || !g->reach_start || !g->body_head || !g->centre_head || !g->scratch || !g->wall_clear_m ||
      index_arena(g, a) != 0) {
    nps_arena_grid_free(g);
    return NULL;
  }
  index_wall_clear(g, a);
  clear_copters(g);
  return g;
}

void nps_arena_grid_free(struct nps_arena_grid *g)
{
  if (!g) {
    return;
  }
  free(g->wall_start);
  free(g->wall_items);
  free(g->reach_start);
  free(g->reach_items);
  free(g->body_head);
  free(g->body_next);
  free(g->centre_head);
  free(g->centre_next);
  free(g->centre_cell);
  free(g->overflow);
  free(g->by_cell);
  free(g->by_cell_xy);
  free(g->copter_box);
  free(g->stay);
  free(g->wall_free);
  free(g->scratch);
  free(g->wall_clear_m);
  free(g);
}

int nps_arena_grid_set_copters(struct nps_arena_grid *g, const struct nps_arena_copter *c, int n)
{
  if (n != g->num_copters && reset_copters(g, n, g->body_shift) != 0) {
    return -1;
  }
  int overflow_changed = 0, centres_changed = 0;
  /* downwards: after a reset every insertion is at the head of its list */
  for (int i = n - 1; i >= 0; i--) {
    if (nps_arena_grid_stays(&g->stay[i], &c[i])) {
      continue;   /* the common case: the same cells as before */
    }
    int box[4], centre;
    const int inside = body_cells(g, &c[i], box, &centre);
    stay_set(g, &g->stay[i], &c[i], box, centre);
    int *old = g->copter_box[i];
    if (box[0] == old[0] && box[1] == old[1] && box[2] == old[2] && box[3] == old[3] && centre == g->centre_cell[i]) {
      continue;
    }
    int shift = g->body_shift;
    while ((box[2] - box[0] + 1) * (box[3] - box[1] + 1) > 1 << shift) {
      shift++;
    }
    if (shift != g->body_shift) {   /* a larger body: room for it, and all again */
      return reset_copters(g, n, shift) != 0 ? -1 : nps_arena_grid_set_copters(g, c, n);
    }
    overflow_changed |= old[0] == -1 || !inside;
    if (old[0] >= 0) {
      link_body(g, i, old, 0);
      list_remove(g->centre_head, g->centre_next, g->centre_cell[i], i);
    }
    if (inside) {
      link_body(g, i, box, 1);
      list_insert(g->centre_head, g->centre_next, centre, i);
    }
    for (int k = 0; k < 4; k++) {
      old[k] = box[k];
    }
    centres_changed |= centre != g->centre_cell[i];
    g->centre_cell[i] = centre;
  }
  if (overflow_changed) {
    list_overflow(g);
  }
  if (centres_changed) {
    sort_by_cell(g);
  }
  return 0;
}

int nps_arena_grid_walk_start(const struct nps_arena_grid *g, const double o[3], const double d[3], double t_max_m,
                              struct nps_arena_grid_walk *w)
{
  const double lo[2] = { g->x0_m, g->y0_m };
  const double hi[2] = { g->x0_m + g->nx * g->cell_m, g->y0_m + g->ny * g->cell_m };
  double t_lo = 0., t_hi = t_max_m;
  /* a ray from inside the grid (nearly all) needs no clipping: the walk ends where it leaves the grid */
  const int inside = nps_arena_grid_cell(g, o[0], o[1]) >= 0;
  for (int k = 0; !inside && k < 2; k++) {
    if (d[k] == 0.) {
      if (o[k] < lo[k] || o[k] >= hi[k]) {
        return 0;
      }
      continue;
    }
    /* no NaN here (finite o and d): plain comparisons instead of the fmin and fmax calls */
    double t1 = (lo[k] - o[k]) / d[k], t2 = (hi[k] - o[k]) / d[k];
    const double t_in = t1 < t2 ? t1 : t2, t_out = t1 < t2 ? t2 : t1;
    t_lo = t_in > t_lo ? t_in : t_lo;
    t_hi = t_out < t_hi ? t_out : t_hi;
  }
  if (!(t_lo <= t_hi)) {
    return 0;
  }
  w->n[0] = g->nx;
  w->n[1] = g->ny;
  w->t_hi = t_hi;
  for (int k = 0; k < 2; k++) {
    double p = o[k] + t_lo * d[k];
    w->idx[k] = clamp_index((p - lo[k]) * g->inv_cell, w->n[k]);
    w->step[k] = d[k] > 0. ? 1 : -1;
    if (d[k] != 0.) {
      w->t_next[k] = (lo[k] + (w->idx[k] + (d[k] > 0. ? 1 : 0)) * g->cell_m - o[k]) / d[k];
      w->t_delta[k] = g->cell_m / fabs(d[k]);
    } else {
      w->t_next[k] = INFINITY;
      w->t_delta[k] = INFINITY;
    }
  }
  w->cell = w->idx[1] * g->nx + w->idx[0];
  w->k = w->t_next[0] < w->t_next[1] ? 0 : 1;
  w->t_exit_m = w->t_next[w->k] < t_hi ? w->t_next[w->k] : t_hi;
  return 1;
}

/** The copters whose body box leaves the grid (they have no cell: every query visits them, last). */
static void visit_overflow(const struct nps_arena *a, nps_arena_copter_visit_fn visit, void *ctx)
{
  const struct nps_arena_grid *g = a->grid;
  for (int k = 0; k < g->num_overflow; k++) {
    visit(ctx, &a->copters[g->overflow[k]]);
  }
}

/** The copters whose centre cell is in the cell box [ix0, ix1] x [iy0, iy1], by a scan of all copters in cell order. */
static void scan_copters(const struct nps_arena *a, int ix0, int iy0, int ix1, int iy1, nps_arena_copter_visit_fn visit,
                         void *ctx)
{
  const struct nps_arena_grid *g = a->grid;
  for (int k = 0; k < g->num_copters; k++) {
    const int ix = g->by_cell_xy[k][0], iy = g->by_cell_xy[k][1];   /* -1 (no cell) is outside every box */
    if (iy >= iy0 && iy <= iy1 && ix >= ix0 && ix <= ix1) {
      visit(ctx, &a->copters[g->by_cell[k]]);
    }
  }
}

void nps_arena_grid_copters_all(const struct nps_arena *a, nps_arena_copter_visit_fn visit, void *ctx)
{
  const struct nps_arena_grid *g = a->grid;
  for (int k = g->num_no_cell; k < g->num_copters; k++) {   /* the copters with a cell: a box of the whole grid */
    visit(ctx, &a->copters[g->by_cell[k]]);
  }
  visit_overflow(a, visit, ctx);
}

void nps_arena_grid_copters_in_box(const struct nps_arena *a, double xlo_m, double ylo_m, double xhi_m, double yhi_m,
                                   nps_arena_copter_visit_fn visit, void *ctx)
{
  const struct nps_arena_grid *g = a->grid;
  int ix0, iy0, ix1, iy1;
  if (!nps_arena_grid_box(g, xlo_m, ylo_m, xhi_m, yhi_m, &ix0, &iy0, &ix1, &iy1)) {
    ix0 = iy0 = 0;
    ix1 = iy1 = -1;
  }
  if (nps_arena_grid_few_copters(g)) {
    scan_copters(a, ix0, iy0, ix1, iy1, visit, ctx);
  } else {
    for (int iy = iy0; iy <= iy1; iy++) {
      for (int ix = ix0; ix <= ix1; ix++) {
        const int cell = iy * g->nx + ix;
        for (int i = g->centre_head[cell]; i >= 0; i = g->centre_next[i]) {
          visit(ctx, &a->copters[i]);
        }
      }
    }
  }
  visit_overflow(a, visit, ctx);
}

void nps_arena_copters_near(const struct nps_arena *a, double x_m, double y_m, double reach_m,
                            nps_arena_copter_visit_fn visit, void *ctx)
{
  nps_arena_grid_copters_in_box(a, x_m - reach_m, y_m - reach_m, x_m + reach_m, y_m + reach_m, visit, ctx);
}
