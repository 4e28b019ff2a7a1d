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

int nps_arena_grid_box(const struct nps_arena_grid *g, double xlo, double ylo, double xhi, double yhi,
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

int nps_arena_grid_cell(const struct nps_arena_grid *g, double x_m, double y_m)
{
  double fx = (x_m - g->x0_m) * g->inv_cell, fy = (y_m - g->y0_m) * g->inv_cell;
  if (!(fx >= 0. && fy >= 0. && fx < g->nx && fy < g->ny)) {
    return -1;
  }
  return (int)fy * g->nx + (int)fx;
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
  size_t n1 = (size_t)(g->nx * g->ny + 1);
  g->wall_start = malloc(n1 * sizeof * g->wall_start);
  g->reach_start = malloc(n1 * sizeof * g->reach_start);
  g->body_start = calloc(n1, sizeof * g->body_start);
  g->centre_start = calloc(n1, sizeof * g->centre_start);
  g->scratch = malloc(n1 * sizeof * g->scratch);
  if (!g->wall_start || !g->reach_start || !g->body_start || !g->centre_start || !g->scratch ||
      index_arena(g, a) != 0) {
    nps_arena_grid_free(g);
    return NULL;
  }
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
  free(g->body_start);
  free(g->body_items);
  free(g->centre_start);
  free(g->centre_items);
  free(g->overflow);
  free(g->copter_box);
  free(g->scratch);
  free(g);
}

/** Body box of copter c in cells; 0 if it is not entirely inside the grid. */
static int body_box(const struct nps_arena_grid *g, const struct nps_arena_copter *c, int b[4])
{
  double r = c->radius_m + NPS_ARENA_GRID_PAD_M;
  double xlo = c->pos_m[0] - r, xhi = c->pos_m[0] + r, ylo = c->pos_m[1] - r, yhi = c->pos_m[1] + r;
  if (!(xlo >= g->x0_m && ylo >= g->y0_m && xhi < g->x0_m + g->nx * g->cell_m && yhi < g->y0_m + g->ny * g->cell_m)) {
    return 0;
  }
  return nps_arena_grid_box(g, xlo, ylo, xhi, yhi, &b[0], &b[1], &b[2], &b[3]);
}

static int grow(void *items, int *capacity, int needed, size_t item_size)
{
  if (needed <= *capacity) {
    return 0;
  }
  int cap = needed > 2 * *capacity ? needed : 2 * *capacity;
  void *p = realloc(*(void **)items, (size_t)cap * item_size);
  if (!p) {
    return -1;
  }
  *(void **)items = p;
  *capacity = cap;
  return 0;
}

int nps_arena_grid_set_copters(struct nps_arena_grid *g, const struct nps_arena_copter *c, int n)
{
  int cells = g->nx * g->ny;
  if (grow(&g->copter_box, &g->copter_box_capacity, n, sizeof * g->copter_box) != 0 ||
      grow(&g->centre_items, &g->centre_capacity, n, sizeof * g->centre_items) != 0 ||
      grow(&g->overflow, &g->overflow_capacity, n, sizeof * g->overflow) != 0) {
    return -1;
  }
  /* boxes and counts: bodies, centres (one cell each), overflow */
  int *centre_count = g->centre_start; /* counted here, turned into offsets below */
  memset(g->scratch, 0, (size_t)cells * sizeof * g->scratch);
  memset(centre_count, 0, (size_t)(cells + 1) * sizeof * centre_count);
  int body_total = 0;
  g->num_overflow = 0;
  for (int i = 0; i < n; i++) {
    int *b = g->copter_box[i];
    if (!body_box(g, &c[i], b)) {
      b[0] = -1;
      g->overflow[g->num_overflow++] = i;
      continue;
    }
    for (int iy = b[1]; iy <= b[3]; iy++) {
      for (int ix = b[0]; ix <= b[2]; ix++) {
        g->scratch[iy * g->nx + ix]++;
      }
    }
    body_total += (b[2] - b[0] + 1) * (b[3] - b[1] + 1);
    centre_count[nps_arena_grid_cell(g, c[i].pos_m[0], c[i].pos_m[1])]++;
  }
  if (grow(&g->body_items, &g->body_capacity, body_total, sizeof * g->body_items) != 0) {
    g->num_overflow = 0;
    memset(g->body_start, 0, (size_t)(cells + 1) * sizeof * g->body_start);
    memset(g->centre_start, 0, (size_t)(cells + 1) * sizeof * g->centre_start);
    return -1;
  }
  counts_to_starts(g, g->body_start);
  for (int i = 0; i < n; i++) {
    const int *b = g->copter_box[i];
    for (int iy = b[1]; b[0] >= 0 && iy <= b[3]; iy++) {
      for (int ix = b[0]; ix <= b[2]; ix++) {
        g->body_items[g->scratch[iy * g->nx + ix]++] = i;
      }
    }
  }
  memcpy(g->scratch, centre_count, (size_t)cells * sizeof * g->scratch);
  counts_to_starts(g, g->centre_start);
  for (int i = 0; i < n; i++) {
    if (g->copter_box[i][0] >= 0) {
      g->centre_items[g->scratch[nps_arena_grid_cell(g, c[i].pos_m[0], c[i].pos_m[1])]++] = i;
    }
  }
  return 0;
}

void nps_arena_grid_walk(const struct nps_arena_grid *g, const double o[3], const double d[3], double t_max_m,
                         nps_arena_grid_visit_fn visit, void *ctx)
{
  const double lo[2] = { g->x0_m, g->y0_m };
  const double hi[2] = { g->x0_m + g->nx * g->cell_m, g->y0_m + g->ny * g->cell_m };
  double t_lo = 0., t_hi = t_max_m;
  for (int k = 0; k < 2; k++) {
    if (d[k] == 0.) {
      if (o[k] < lo[k] || o[k] >= hi[k]) {
        return;
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
    return;
  }
  const int n[2] = { g->nx, g->ny };
  int idx[2], step[2];
  double t_next[2], t_delta[2];
  for (int k = 0; k < 2; k++) {
    double p = o[k] + t_lo * d[k];
    idx[k] = clamp_index((p - lo[k]) * g->inv_cell, n[k]);
    step[k] = d[k] > 0. ? 1 : -1;
    if (d[k] != 0.) {
      t_next[k] = (lo[k] + (idx[k] + (d[k] > 0. ? 1 : 0)) * g->cell_m - o[k]) / d[k];
      t_delta[k] = g->cell_m / fabs(d[k]);
    } else {
      t_next[k] = INFINITY;
      t_delta[k] = INFINITY;
    }
  }
  for (;;) {
    int k = t_next[0] < t_next[1] ? 0 : 1;
    double t_exit = t_next[k] < t_hi ? t_next[k] : t_hi;
    if (visit(ctx, idx[1] * g->nx + idx[0], t_exit) || t_exit >= t_hi) {
      return;
    }
    idx[k] += step[k];
    if (idx[k] < 0 || idx[k] >= n[k]) {
      return;
    }
    t_next[k] += t_delta[k];
  }
}

void nps_arena_grid_copters_in_box(const struct nps_arena *a, double xlo_m, double ylo_m, double xhi_m, double yhi_m,
                                   nps_arena_copter_visit_fn visit, void *ctx)
{
  const struct nps_arena_grid *g = a->grid;
  int ix0, iy0, ix1, iy1;
  if (nps_arena_grid_box(g, xlo_m, ylo_m, xhi_m, yhi_m, &ix0, &iy0, &ix1, &iy1)) {
    for (int iy = iy0; iy <= iy1; iy++) {
      for (int ix = ix0; ix <= ix1; ix++) {
        const int cell = iy * g->nx + ix;
        for (int k = g->centre_start[cell]; k < g->centre_start[cell + 1]; k++) {
          visit(ctx, &a->copters[g->centre_items[k]]);
        }
      }
    }
  }
  for (int k = 0; k < g->num_overflow; k++) {   /* copters outside the grid */
    visit(ctx, &a->copters[g->overflow[k]]);
  }
}

void nps_arena_copters_near(const struct nps_arena *a, double x_m, double y_m, double reach_m,
                            nps_arena_copter_visit_fn visit, void *ctx)
{
  nps_arena_grid_copters_in_box(a, x_m - reach_m, y_m - reach_m, x_m + reach_m, y_m + reach_m, visit, ctx);
}
