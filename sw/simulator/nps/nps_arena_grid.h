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
 * which copters are in each cell (updated every step, for the copters that changed cells). It replaces
 * every copter x segment and copter x copter scan: a copter looks up the walls that can feel it in its own
 * cell, a ray walks the cells it crosses (Amanatides & Woo, "A fast voxel traversal algorithm",
 * Eurographics 1987) and tests the walls whose plates can reach the cells (only the plates of a wall the
 * ray can meet: nps_raycast.c) and the copters listed there, a beam looks at the copters in the cells
 * within its range.
 */

#ifndef NPS_ARENA_GRID_H
#define NPS_ARENA_GRID_H

#include "nps_arena.h"

/** The grid never has more cells than this (the cell grows instead). */
#define NPS_ARENA_GRID_MAX_CELLS (1 << 20)

/** Boxes grow by this much before they are put in cells: a point on a cell border is in both [m]. */
#define NPS_ARENA_GRID_PAD_M 1e-9

/**
 * The centres a copter may move to while its body box cells, centre cell and radius stay those indexed: the open
 * rectangle (lo, hi), the exact cell borders shrunk by far more than the rounding of the cell computations (so
 * a copter within it surely has the indexed cells, and a step of a copter that stays in its cells costs four
 * comparisons); empty (lo > hi) when not indexed or outside the grid.
 */
struct nps_arena_grid_stay {
  double lo[2], hi[2];     /**< open box of the centre [m] */
  double radius_m;         /**< the body radius indexed [m] */
};

/**
 * Where the walls step (nps_walls_step.c) last tested a copter against the walls of its centre cell: a centre from
 * which none of them is within its threshold, not even from any centre of the same cell less than slack_m away
 * (|dx| + |dy|, see there); while the copter stays that close, the step skips the test. cell -1: nothing known.
 */
struct nps_arena_grid_wall_free {
  double x_m, y_m;         /**< centre tested [m] */
  double slack_m;          /**< how far (|dx| + |dy|) it may move with the same answer [m]; < 0 when a wall was near */
  int cell;                /**< its centre cell, -1: no test yet */
};

/**
 * Walls: compressed lists (CSR) per cell, built once: items of cell c are items[start[c] .. start[c+1]-1].
 * Copters: linked lists per cell, kept up to date copter by copter (nps_arena_grid_set_copters): a step
 * costs in proportion to the copters, and nothing for a copter that stays in its cells. Every cell's list
 * is in ascending copter order (the order of a full rebuild by counting sort, on which the visit order of
 * nps_arena_grid_copters_in_box, and so the contacts and the ranging draws, depend).
 */
struct nps_arena_grid {
  double x0_m, y0_m;       /**< lower-left corner of the grid [m] */
  double cell_m;           /**< cell side [m] */
  double inv_cell;         /**< 1 / cell_m [1/m] */
  int nx, ny;              /**< cells along x and y */
  int *wall_start, *wall_items;     /**< walls within their threshold of the cell (box test) */
  int *reach_start, *reach_items;   /**< walls whose plates can reach into the cell (hinge height, box test) */
  int *body_head;          /**< per cell: first entry of the copters whose body box overlaps it, -1: none */
  int *body_next;          /**< per entry: the next entry of the same cell, -1: none. Copter i owns the entries
                                (i << body_shift) + k, one per cell of its body box (k in row order) */
  int body_shift;          /**< log2 of the entries per copter: 1 << body_shift >= cells of any body box */
  int *centre_head;        /**< per cell: first copter whose centre is in it, -1: none */
  int *centre_next;        /**< per copter: the next copter of the same cell, -1: none */
  int *centre_cell;        /**< per copter: the cell of its centre; -1 in the overflow list or not indexed */
  int (*copter_box)[4];    /**< per copter: cell range of its body box; [0] = -1 overflow, -2 not indexed */
  struct nps_arena_grid_stay *stay; /**< per copter: where its centre may move with no change of its cells */
  struct nps_arena_grid_wall_free *wall_free; /**< per copter: its last test against the walls (walls step) */
  int *by_cell;            /**< all copters sorted by (centre_cell, index): a few copters are scanned in this
                                order instead of the cells (the same visits, in the same order) */
  int (*by_cell_xy)[2];    /**< per entry of by_cell: column and row of that copter's centre cell, -1 -1 if none */
  int num_no_cell;         /**< the first entries of by_cell: the copters with no centre cell (they sort first) */
  int *overflow;           /**< copters whose body box leaves the grid, ascending: always tested */
  int num_overflow;
  int num_copters;         /**< copters indexed */
  int copter_capacity;     /**< copters the per-copter arrays hold */
  int *scratch;            /**< per-cell counters (building the wall lists) */
  double *wall_clear_m;    /**< per cell: a copter centred in it with a radius below this is pushed by no wall
                                and no obstacle (nps_arena_contact.c; -INFINITY everywhere with more than direct_max_walls walls) [m] */
  int direct_max_copters;  /**< up to this many copters, a ray cast tests each copter and a box query scans
                                them (by_cell) instead of the cells (tests change it to compare the two ways) */
  int direct_max_walls;    /**< up to this many walls, a ray cast that tests each copter also tests each wall
                                instead of walking the cells for them (tests change it to compare the two ways) */
};

/** Default of direct_max_copters: below, testing each copter costs less than looking them up in cells. */
#define NPS_ARENA_GRID_DIRECT_MAX 8
/**
 * Default of direct_max_walls: rejecting a wall the ray cannot meet from its track costs a few dozen instructions,
 * less than walking the cells of a small arena (and a wall behind a copter hit is rejected at once).
 */
#define NPS_ARENA_GRID_DIRECT_WALLS 8

/** Build the grid of a's walls and segments (cell: the largest threshold or hinge height). NULL on ENOMEM. */
struct nps_arena_grid *nps_arena_grid_new(const struct nps_arena *a);

/** Free (NULL is fine). */
void nps_arena_grid_free(struct nps_arena_grid *g);

/**
 * Re-index the copters c[0 .. n-1] (copter i keeps index i): only a copter whose body box or centre cell
 * changed since the last call is moved between lists; a different n rebuilds all.
 * @return 0, or -1 on ENOMEM (the index is then empty; n = 0 needs no memory)
 */
int nps_arena_grid_set_copters(struct nps_arena_grid *g, const struct nps_arena_copter *c, int n);

/** The cell containing (x, y), or -1 outside the grid. */
int nps_arena_grid_cell(const struct nps_arena_grid *g, double x_m, double y_m);

/** Whether copter c surely has the cells it was indexed with (its centre within its stay box, the same radius). */
static inline int nps_arena_grid_stays(const struct nps_arena_grid_stay *s, const struct nps_arena_copter *c)
{
  return c->pos_m[0] > s->lo[0] && c->pos_m[0] < s->hi[0] && c->pos_m[1] > s->lo[1] && c->pos_m[1] < s->hi[1] &&
         c->radius_m == s->radius_m;
}

/**
 * nps_arena_grid_cell of the centre of copter i of the indexed copters c: its indexed centre cell while it stays
 * in its cells (a few comparisons), else worked out.
 */
static inline int nps_arena_grid_copter_cell(const struct nps_arena_grid *g, const struct nps_arena_copter *c, int i)
{
  return i < g->num_copters && nps_arena_grid_stays(&g->stay[i], c) ? g->centre_cell[i]
         : nps_arena_grid_cell(g, c->pos_m[0], c->pos_m[1]);
}

/**
 * nps_arena_grid_cell of the centre of copter i of the indexed copters c while the index is current (nothing moved
 * since the last nps_arena_grid_set_copters, as after nps_arena_set_copters, nps_arena_poses_moved and the contacts):
 * its indexed centre cell (a load), worked out only for a copter whose body box leaves the grid (indexed with no cell).
 */
static inline int nps_arena_grid_indexed_cell(const struct nps_arena_grid *g, const struct nps_arena_copter *c, int i)
{
  return g->centre_cell[i] >= 0 ? g->centre_cell[i] : nps_arena_grid_cell(g, c->pos_m[0], c->pos_m[1]);
}

/** Cell index ranges [*ix0, *ix1] x [*iy0, *iy1] overlapping the box; 0 if the box misses the grid. */
int nps_arena_grid_box(const struct nps_arena_grid *g, double xlo, double ylo, double xhi, double yhi,
                       int *ix0, int *iy0, int *ix1, int *iy1);

/**
 * A walk along the cells a ray o + t d (d unit), t in [0, t_max_m], crosses, in order (Amanatides & Woo):
 *   for (int more = nps_arena_grid_walk_start(g, o, d, t_max_m, &w); more; more = nps_arena_grid_walk_next(&w))
 *     ... w.cell, left at t = w.t_exit_m ...
 * A vertical ray visits one cell.
 */
struct nps_arena_grid_walk {
  int cell;                /**< the cell the ray is in */
  double t_exit_m;         /**< where the ray leaves it [m] */
  int idx[2], step[2], n[2], k;
  double t_next[2], t_delta[2], t_hi;
};

/** Start a walk at the first cell of the ray in the grid. @return 0 if the ray misses the grid */
int nps_arena_grid_walk_start(const struct nps_arena_grid *g, const double o[3], const double d[3], double t_max_m,
                              struct nps_arena_grid_walk *w);

/** Go to the next cell. @return 0 at the end of the ray or of the grid */
static inline int nps_arena_grid_walk_next(struct nps_arena_grid_walk *w)
{
  const int k = w->k;
  if (w->t_exit_m >= w->t_hi) {
    return 0;
  }
  w->idx[k] += w->step[k];
  if (w->idx[k] < 0 || w->idx[k] >= w->n[k]) {
    return 0;
  }
  w->cell += k == 0 ? w->step[0] : w->step[1] * w->n[0];
  w->t_next[k] += w->t_delta[k];
  w->k = w->t_next[0] < w->t_next[1] ? 0 : 1;
  w->t_exit_m = w->t_next[w->k] < w->t_hi ? w->t_next[w->k] : w->t_hi;
  return 1;
}

/**
 * Visit every copter whose centre lies in the box [xlo, xhi] x [ylo, yhi] [m] (cells overlapping it, so some
 * outside too; callers apply their own exact test) and every copter outside the grid.
 */
void nps_arena_grid_copters_in_box(const struct nps_arena *a, double xlo_m, double ylo_m, double xhi_m, double yhi_m,
                                   nps_arena_copter_visit_fn visit, void *ctx);

/**
 * Visit every copter, in the order nps_arena_grid_copters_in_box visits those of any box (the copters with a
 * centre cell by cell, then those outside the grid): the visits of a box query are those of this scan that fall
 * in the box, in the same order.
 */
void nps_arena_grid_copters_all(const struct nps_arena *a, nps_arena_copter_visit_fn visit, void *ctx);

/**
 * Whether the swarm is small enough (direct_max_copters) that a query whose box holds much of it had better visit
 * every copter (nps_arena_grid_copters_all, with no box to work out) and leave the rest to its exact test.
 */
static inline int nps_arena_grid_few_copters(const struct nps_arena_grid *g)
{
  return g->num_copters <= g->direct_max_copters;
}

#endif /* NPS_ARENA_GRID_H */
