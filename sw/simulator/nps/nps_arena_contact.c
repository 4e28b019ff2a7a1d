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
 * Whether the body of radius c_radius_m centred at c_m[0..1] (a copter's, or where it would be) overlaps copter o's
 * (nps_arena_bodies_overlap; *d_m receives their centre distance when it was worked out): the one test that decides
 * whether separate() pushes two copters.
 */
static inline int bodies_overlap(const double c_m[2], double c_radius_m, const struct nps_arena_copter *o, double *d_m)
{
  return nps_arena_bodies_overlap(o->pos_m[0] - c_m[0], o->pos_m[1] - c_m[1], c_radius_m + o->radius_m, d_m);
}

/**
 * How far copter o moves when overlapping copters c and o (centre distance d_m) are pushed apart [m]: each by half
 * the overlap along the line of their centres, o away from c, c by the opposite. Coincident centres separate along
 * x, the lower index going west.
 */
static void contact_shift(const struct nps_arena_copter *c, const struct nps_arena_copter *o, double d_m,
                          double shift_m[2])
{
  const double dx = o->pos_m[0] - c->pos_m[0], dy = o->pos_m[1] - c->pos_m[1];
  const double reach = c->radius_m + o->radius_m;
  const double ux = d_m > 0.0 ? dx / d_m : 1.0, uy = d_m > 0.0 ? dy / d_m : 0.0;
  const double half = 0.5 * (reach - d_m);
  shift_m[0] = half * ux;
  shift_m[1] = half * uy;
}

/** Push copters i and j apart by shift_m (contact_shift) and count the contact. */
static void push_apart(struct contact_pass *pass, int i, int j, const double shift_m[2])
{
  struct nps_arena_copter *c = &pass->a->copters[i], *o = &pass->a->copters[j];
  c->pos_m[0] -= shift_m[0];
  c->pos_m[1] -= shift_m[1];
  o->pos_m[0] += shift_m[0];
  o->pos_m[1] += shift_m[1];
  mark(pass, i);
  mark(pass, j);
  pass->count++;
}

/** Push copter self and a neighbour q apart (each pair once: the one with the lower index does it). */
static void separate(void *ctx, const struct nps_arena_copter *q)
{
  struct contact_pass *pass = ctx;
  const struct nps_arena_copter *c = &pass->a->copters[pass->self];
  const int j = (int)(q - pass->a->copters);
  double d_m, shift_m[2];
  if (j <= pass->self || !bodies_overlap(c->pos_m, c->radius_m, q, &d_m)) {
    return;
  }
  contact_shift(c, q, d_m, shift_m);
  push_apart(pass, pass->self, j, shift_m);
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
 * The copters j > i (the only ones separate() pushes from i) whose body overlaps copter i's, centred at c_m[0..1]
 * (where it is, or would be), leaving out copter skip: -1 if none, the copter if one (*d_m: its centre distance),
 * -2 if more.
 */
static inline int later_overlap(const struct nps_arena *a, int i, const double c_m[2], int skip, double *d_m)
{
  const double radius_m = a->copters[i].radius_m;
  int found = -1;
  for (int j = i + 1; j < a->num_copters; j++) {
    double d_j_m;
    if (j != skip && bodies_overlap(c_m, radius_m, &a->copters[j], &d_j_m)) {
      if (found >= 0) {
        return -2;
      }
      found = j;
      *d_m = d_j_m;
    }
  }
  return found;
}

/**
 * Copter i's neighbour query done here, for a swarm of a few copters (nps_arena_grid_few_copters), when the outcome
 * is surely that of the query: the query runs separate() on a subset of the copters, and positions change only by
 * a push. No later copter overlapping copter i: nothing to do. Exactly one, j, while nothing was pushed yet in
 * this pass (the index is current, so the query visits j: its centre lies within the query's box) and no other
 * later copter overlaps copter i at its pushed place: the query pushes i and j apart and nothing else, whatever
 * its order. Returns 0 (nothing done) when the query must decide.
 */
static int query_done_here(struct contact_pass *pass, int i)
{
  const struct nps_arena *a = pass->a;
  const struct nps_arena_copter *c = &a->copters[i];
  double d_m = 0.0, shift_m[2];
  const int j = later_overlap(a, i, c->pos_m, -1, &d_m);
  if (j == -1) {
    return 1;
  }
  if (j < 0 || pass->count > 0) {
    return 0;
  }
  contact_shift(c, &a->copters[j], d_m, shift_m);
  const double pushed_m[2] = { c->pos_m[0] - shift_m[0], c->pos_m[1] - shift_m[1] };
  if (later_overlap(a, i, pushed_m, j, &d_m) != -1) {
    return 0;
  }
  push_apart(pass, i, j, shift_m);
  return 1;
}

/** Whether copter i surely needs no neighbour query in this contact pass (having done it here if it could). */
static int needs_no_query(struct contact_pass *pass, int i)
{
  if (nps_arena_grid_few_copters(pass->a->grid)) {
    return query_done_here(pass, i);
  }
  return pass->count == 0 && body_alone(pass->a->grid, i);   /* nothing pushed yet, and no other body in its cells */
}

/**
 * Keep copter c inside every wall (at least its radius from the wall's line, where it faces the wall) and out of
 * every obstacle that reaches above its body's bottom. indexed: no copter moved since the index was made (its cell
 * is then the indexed one).
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
  for (int k = 0; k < a->num_obstacles; k++) {
    const struct nps_obstacle *o = &a->obstacles[k];
    if (o->height_m > c->pos_m[2] - 0.5 * c->height_m) {
      pushed |= nps_obstacle_push_out(o, c->pos_m, c->radius_m);
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
    if (needs_no_query(&pass, i)) {
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
