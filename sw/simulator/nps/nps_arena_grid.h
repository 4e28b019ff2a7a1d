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
 * @file nps_arena_grid.h
 * Uniform grid over the arena: which walls and wall segments can matter in each cell (built once) and
 * which copters are in each cell (rebuilt every step by counting sort). It replaces every copter x segment
 * and copter x copter scan: a copter looks up the walls that can feel it in its own cell, a ray walks the
 * cells it crosses (Amanatides & Woo, "A fast voxel traversal algorithm", Eurographics 1987) and tests
 * the walls whose plates can reach the cells (only the plates of a wall the ray can meet: nps_raycast.c)
 * and the copters listed there, a beam looks at the copters in the cells within its range.
 */

#ifndef NPS_ARENA_GRID_H
#define NPS_ARENA_GRID_H

#include "nps_arena.h"

/** The grid never has more cells than this (the cell grows instead). */
#define NPS_ARENA_GRID_MAX_CELLS (1 << 20)

/** Boxes grow by this much before they are put in cells: a point on a cell border is in both [m]. */
#define NPS_ARENA_GRID_PAD_M 1e-9

/** Compressed lists (CSR) per cell: items of cell c are items[start[c] .. start[c+1]-1]. */
struct nps_arena_grid {
  double x0_m, y0_m;       /**< lower-left corner of the grid [m] */
  double cell_m;           /**< cell side [m] */
  double inv_cell;         /**< 1 / cell_m [1/m] */
  int nx, ny;              /**< cells along x and y */
  int *wall_start, *wall_items;     /**< walls within their threshold of the cell (box test) */
  int *reach_start, *reach_items;   /**< walls whose plates can reach into the cell (hinge height, box test) */
  int *body_start, *body_items;     /**< copters whose body box overlaps the cell */
  int body_capacity;
  int *centre_start, *centre_items; /**< copters whose centre is in the cell */
  int centre_capacity;
  int *overflow;           /**< copters whose body box leaves the grid: always tested */
  int num_overflow;
  int overflow_capacity;
  int (*copter_box)[4];    /**< per copter: cell range of its body box, [0] = -1 for overflow */
  int copter_box_capacity;
  int *scratch;            /**< per-cell counters */
};

/** Build the grid of a's walls and segments (cell: the largest threshold or hinge height). NULL on ENOMEM. */
struct nps_arena_grid *nps_arena_grid_new(const struct nps_arena *a);

/** Free (NULL is fine). */
void nps_arena_grid_free(struct nps_arena_grid *g);

/** Re-index the copters. @return 0, or -1 on ENOMEM */
int nps_arena_grid_set_copters(struct nps_arena_grid *g, const struct nps_arena_copter *c, int n);

/** The cell containing (x, y), or -1 outside the grid. */
int nps_arena_grid_cell(const struct nps_arena_grid *g, double x_m, double y_m);

/** Cell index ranges [*ix0, *ix1] x [*iy0, *iy1] overlapping the box; 0 if the box misses the grid. */
int nps_arena_grid_box(const struct nps_arena_grid *g, double xlo, double ylo, double xhi, double yhi,
                       int *ix0, int *iy0, int *ix1, int *iy1);

/**
 * Called for each cell a ray crosses, in order. t_exit_m: distance along the ray where it leaves the cell.
 * @return 1 to stop the walk (the caller found a hit before t_exit_m), 0 to go on
 */
typedef int (*nps_arena_grid_visit_fn)(void *ctx, int cell, double t_exit_m);

/** Walk the cells crossed by o + t d, t in [0, t_max_m] (d unit; vertical rays visit one cell). */
void nps_arena_grid_walk(const struct nps_arena_grid *g, const double o[3], const double d[3], double t_max_m,
                         nps_arena_grid_visit_fn visit, void *ctx);

/**
 * Visit every copter whose centre lies in the box [xlo, xhi] x [ylo, yhi] [m] (cells overlapping it, so some
 * outside too; callers apply their own exact test) and every copter outside the grid.
 */
void nps_arena_grid_copters_in_box(const struct nps_arena *a, double xlo_m, double ylo_m, double xhi_m, double yhi_m,
                                   nps_arena_copter_visit_fn visit, void *ctx);

#endif /* NPS_ARENA_GRID_H */
