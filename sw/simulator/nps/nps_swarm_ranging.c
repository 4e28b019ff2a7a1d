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
 * @file nps_swarm_ranging.c
 * Simulated radio ranging between FINken: omnidirectional, not occluded, only equipped copters, no direction
 * (report, section 4.1); error from the ranging chain of the sensor model.
 */

#include "nps_swarm_world.h"
#include "nps_arena_grid.h"

#include <math.h>
#include <stdlib.h>

/** Radio horizon as a multiple of the ranging maximum: farther peers are not heard at all. */
#define NPS_SWARM_RANGING_HORIZON 2.0

void nps_swarm_ranging_disable(void)
{
  nps_swarm_world.ranging_disabled = true;
}

void nps_swarm_ranging_equip(unsigned v)
{
  nps_swarm_world.vehicles[v].ranging_equipped = true;
}

struct ranging_pass {
  unsigned v;
  double now_s, horizon_m;
  struct nps_sensor_ctx ctx; ///< what every peer's context shares: copter v's id, speed and wall distance (0 if unread)
  bool find_blocked;        ///< whether ctx_blocked is read by the chain or the log (else left 0)
  gsl_rng *rng;             ///< copter v's ranging stream
  const struct nps_sensor_chain *chain;
  nps_swarm_ranging_report_fn report;
  void *report_ctx;
};

/** The stream state of the pair (v, peer), allocated on first use; NULL when the model has no latency. */
static struct nps_sensor_state *pair_state(unsigned v, unsigned peer)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  if (w->ranging_state == NULL) {
    return NULL;
  }
  struct nps_sensor_state **slot = &w->ranging_state[(size_t)v * w->n + peer];
  if (*slot == NULL && (*slot = malloc(sizeof(**slot))) != NULL) {
    nps_sensor_state_init(*slot);
  }
  return *slot;
}

static void measure_peer(void *ctx_ptr, const struct nps_arena_copter *q)
{
  struct ranging_pass *pass = ctx_ptr;
  const struct nps_swarm_world *w = &nps_swarm_world;
  const struct nps_arena_copter *c = nps_swarm_copter(pass->v);
  const unsigned peer = nps_swarm_vehicle_of((unsigned)q->id);
  if (peer == pass->v) {   /* itself: no distance to work out */
    return;
  }
  const double dx_m = q->pos_m[0] - c->pos_m[0], dy_m = q->pos_m[1] - c->pos_m[1], dz_m = q->pos_m[2] - c->pos_m[2];
  const double true_range_m = sqrt(dx_m * dx_m + dy_m * dy_m + dz_m * dz_m);
  /* the horizon before the peer's equipment: it rejects the corners of the search box (a fifth of the candidates)
   * without touching the peer's vehicle record */
  if (true_range_m > pass->horizon_m || !w->vehicles[peer].ranging_equipped) {
    return;
  }
  /* the shared context as it is, unless this pair's line of sight is wanted (a copy: 17 numbers per peer) */
  const struct nps_sensor_ctx *ctx = &pass->ctx;
  struct nps_sensor_ctx pair_ctx;
  if (pass->find_blocked) {
    pair_ctx = pass->ctx;
    pair_ctx.blocked = nps_raycast_line_blocked(w->arena, c->pos_m, q->pos_m, c->id, q->id, NULL);
    ctx = &pair_ctx;
  }
  const double measured_m = pass->chain != NULL
                            ? nps_sensor_chain_apply(pass->chain, pass->now_s, true_range_m, ctx, pair_state(pass->v, peer),
                                pass->rng)
                            : true_range_m;
  nps_range_log_write(&nps_swarm_world.log, pass->now_s, nps_swarm_id(pass->v), "ranging", q->id, true_range_m, measured_m, ctx);
  if (!isnan(measured_m)) {
    pass->report(pass->report_ctx, (uint16_t)q->id, measured_m);
  }
}

void nps_swarm_ranging_measure(unsigned v, double now_s, nps_swarm_ranging_report_fn report, void *ctx)
{
  const struct nps_swarm_world *w = &nps_swarm_world;
  if (!w->vehicles[v].ranging_equipped || w->ranging_disabled) {
    return;
  }
  if (w->before_read != NULL) {
    w->before_read();
  }
  struct ranging_pass pass = {
    .v = v, .now_s = now_s + w->clock_offset_s, .rng = w->vehicles[v].ranging_rng,
    .ctx.speed_mps = w->vehicles[v].speed_mps, .ctx.vehicle = nps_swarm_id(v),
    /* the chain by kind, not by name: this runs for every copter 10 times a second */
    .chain = nps_sensor_model_chain_of(w->model, NPS_SENSOR_RANGING),
    .report = report, .report_ctx = ctx,
  };
  pass.horizon_m = NPS_SWARM_RANGING_HORIZON * (pass.chain != NULL ? pass.chain->max_range_m : 2.5);
  const struct nps_arena_copter *c = nps_swarm_copter(v);
  /* ranging is not occluded: ctx_blocked and ctx_wall_dist only matter to a chain that names them and to the log */
  pass.find_blocked = nps_swarm_needs_ctx(NPS_SENSOR_RANGING, NPS_CTX_BLOCKED);
  if (nps_swarm_needs_ctx(NPS_SENSOR_RANGING, NPS_CTX_WALL_DIST)) {
    pass.ctx.wall_dist_m = nps_raycast_wall_dist(w->arena, c->pos_m);
  }
  if (nps_arena_grid_few_copters(w->arena->grid)) {   /* a few copters: the horizon's box would hold most */
    nps_arena_grid_copters_all(w->arena, measure_peer, &pass);
  } else {
    nps_arena_copters_near(w->arena, c->pos_m[0], c->pos_m[1], pass.horizon_m, measure_peer, &pass);
  }
}

double nps_swarm_ranging_pairs_in_horizon(void)
{
  const struct nps_swarm_world *w = &nps_swarm_world;
  const struct nps_sensor_chain *chain = nps_sensor_model_chain_of(w->model, NPS_SENSOR_RANGING);
  const double horizon_m = NPS_SWARM_RANGING_HORIZON * (chain != NULL ? chain->max_range_m : 2.5);
  double pairs = 0.0;
  for (unsigned v = 0; v < w->n; v++) {
    if (!nps_swarm_present(v) || !w->vehicles[v].ranging_equipped) {
      continue;
    }
    const double *p = nps_swarm_copter(v)->pos_m;
    for (unsigned u = 0; u < w->n; u++) {
      if (u != v && nps_swarm_present(u) && w->vehicles[u].ranging_equipped) {
        const double *q = nps_swarm_copter(u)->pos_m;
        pairs += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]))
                 <= horizon_m;
      }
    }
  }
  return pairs;
}
