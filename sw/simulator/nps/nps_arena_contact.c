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
 * @file nps_arena_contact.c
 * Contacts in the arena (see nps_arena_contact.h).
 */

#include "nps_arena_contact.h"
#include "nps_arena_grid.h"

#include <math.h>
#include <string.h>

struct contact_pass {
  struct nps_arena *a;
  int self;          ///< index of the copter whose neighbours are visited
  int *moved;
  int count;
};

static void mark(struct contact_pass *pass, int i)
{
  if (pass->moved != NULL && !pass->moved[i]) {
    pass->moved[i] = 1;
  }
}

/**
 * Whether two centres dx, dy apart [m] surely do not overlap for bodies `reach` apart: exact quick reject of
 * the distance sqrt(dx^2 + dy^2) computed in separate(), which is >= max(|dx|, |dy|) in floating point too:
 * sqrt(fl(x * x)) == |x| exactly when rounding to nearest without underflow, and adding fl(dy^2) >= 0, the
 * rounding and sqrt are monotone.
 */
static inline int surely_apart(double dx, double dy, double reach)
{
  return fabs(dx) >= reach || fabs(dy) >= reach;
}

/** Push copter self and a neighbour q apart (each pair once: the one with the lower index does it). */
static void separate(void *ctx, const struct nps_arena_copter *q)
{
  struct contact_pass *pass = ctx;
  struct nps_arena_copter *c = &pass->a->copters[pass->self];
  const int j = (int)(q - pass->a->copters);
  if (j <= pass->self) {
    return;
  }
  struct nps_arena_copter *o = &pass->a->copters[j];
  const double dx = o->pos_m[0] - c->pos_m[0], dy = o->pos_m[1] - c->pos_m[1];
  const double reach = c->radius_m + o->radius_m;
  if (surely_apart(dx, dy, reach)) {
    return;
  }
  /* no hypot call: centre distances in metres neither overflow nor underflow when squared */
  const double d = sqrt(dx * dx + dy * dy);
  if (d >= reach) {
    return;
  }
  /* coincident centres: separate along x, the lower index going west */
  const double ux = d > 0.0 ? dx / d : 1.0, uy = d > 0.0 ? dy / d : 0.0;
  const double half = 0.5 * (reach - d);
  c->pos_m[0] -= half * ux;
  c->pos_m[1] -= half * uy;
  o->pos_m[0] += half * ux;
  o->pos_m[1] += half * uy;
  mark(pass, pass->self);
  mark(pass, j);
  pass->count++;
}

/**
 * Whether copter i can touch no other copter: its body box cells hold no other body (two bodies that overlap
 * share a cell of their boxes). Only valid while every position is the indexed one (no push yet this pass).
 */
static int body_alone(const struct nps_arena_grid *g, int i)
{
  const int *box = g->copter_box[i];
  if (box[0] < 0) {   /* outside the grid, or not indexed */
    return 0;
  }
  for (int iy = box[1]; iy <= box[3]; iy++) {
    for (int ix = box[0]; ix <= box[2]; ix++) {
      const int e = g->body_head[iy * g->nx + ix];
      if (e < 0 || g->body_next[e] >= 0) {
        return 0;
      }
    }
  }
  return 1;
}

/**
 * Whether separate() would leave copter i alone with every copter j > i (the only ones it pushes from i), at their
 * current positions: a test of each such copter, for a swarm of a few copters (nps_arena_grid_few_copters).
 * The box query visits a subset of these copters, so the query can only do something when this is false.
 */
static int no_later_copter_near(const struct nps_arena *a, int i)
{
  const struct nps_arena_copter *c = &a->copters[i];
  for (int j = i + 1; j < a->num_copters; j++) {
    const struct nps_arena_copter *o = &a->copters[j];
    if (!surely_apart(o->pos_m[0] - c->pos_m[0], o->pos_m[1] - c->pos_m[1], c->radius_m + o->radius_m)) {
      return 0;
    }
  }
  return 1;
}

/** Whether copter i surely needs no neighbour query in this contact pass (after `pushed` pushes so far). */
static int needs_no_query(const struct nps_arena *a, int i, int pushed)
{
  if (nps_arena_grid_few_copters(a->grid)) {
    return no_later_copter_near(a, i);
  }
  return pushed == 0 && body_alone(a->grid, i);   /* nothing pushed yet, and no other body in its cells */
}

/**
 * Keep copter c inside every wall: at least its radius from the wall's line, where it faces the wall. indexed: no
 * copter moved since the index was made (its cell is then the indexed one).
 */
static int stay_inside(const struct nps_arena *a, int i, int indexed)
{
  struct nps_arena_copter *c = &a->copters[i];
  const int cell = indexed ? nps_arena_grid_indexed_cell(a->grid, c, i) : nps_arena_grid_copter_cell(a->grid, c, i);
  if (cell >= 0 && c->radius_m < a->grid->wall_clear_m[cell]) {
    return 0;   /* far enough inside every wall it faces (nps_arena_grid.h) */
  }
  int pushed = 0;
  for (int w = 0; w < a->num_walls; w++) {
    const struct nps_wall *wall = &a->walls[w];
    const double rx = c->pos_m[0] - wall->a[0], ry = c->pos_m[1] - wall->a[1];
    const double along = rx * wall->t[0] + ry * wall->t[1];
    const double inside = rx * wall->n[0] + ry * wall->n[1];
    if (along >= 0.0 && along <= wall->length_m && inside < c->radius_m) {
      c->pos_m[0] += (c->radius_m - inside) * wall->n[0];
      c->pos_m[1] += (c->radius_m - inside) * wall->n[1];
      pushed = 1;
    }
  }
  return pushed;
}

/** The largest body radius of a's copters (0 with none) [m]. */
static double max_radius(const struct nps_arena *a)
{
  double max_radius_m = 0.0;
  for (int i = 0; i < a->num_copters; i++) {
    /* fmax(max_radius_m, r) without the call: max_radius_m is never NaN, and a NaN r leaves it as fmax does */
    max_radius_m = a->copters[i].radius_m > max_radius_m ? a->copters[i].radius_m : max_radius_m;
  }
  return max_radius_m;
}

int nps_arena_resolve_contacts(struct nps_arena *a, int *moved)
{
  struct contact_pass pass = { .a = a, .moved = moved };
  if (moved != NULL) {
    memset(moved, 0, (size_t)a->num_copters * sizeof(*moved));
  }
  double max_radius_m = -1.0;   /* worked out at the first query (most passes need none) */
  for (int i = 0; i < a->num_copters; i++) {
    if (needs_no_query(a, i, pass.count)) {
      continue;
    }
    if (max_radius_m < 0.0) {
      max_radius_m = max_radius(a);
    }
    pass.self = i;
    nps_arena_copters_near(a, a->copters[i].pos_m[0], a->copters[i].pos_m[1], a->copters[i].radius_m + max_radius_m,
                           separate, &pass);
  }
  int count = pass.count;
  for (int i = 0; i < a->num_copters; i++) {
    if (stay_inside(a, i, pass.count == 0)) {   /* a wall push before moved only the copter it pushed */
      mark(&pass, i);
      count++;
    }
  }
  if (count > 0 && nps_arena_grid_set_copters(a->grid, a->copters, a->num_copters) < 0) {
    return -1;
  }
  return count;
}
