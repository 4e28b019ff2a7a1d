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
 * @file nps_sensor_model_ctx.c
 * Context slots of a reading, which of them a chain reads, and the per-stream true-range history.
 */

#include "nps_sensor_model_ctx.h"
#include "nps_sensor_model.h"

#include <math.h>

static const char *const fixed_names[NPS_CTX_EXTRA0] = {
  "ctx_facing_sonars", "ctx_target_copter", "ctx_blocked", "ctx_wall_dist", "ctx_speed",
  "ctx_crosstalk_path", "ctx_trigger_offset", "ctx_floor", "ctx_target_obstacle", "ctx_vehicle",
};

static double *slot_ptr(struct nps_sensor_ctx *ctx, int slot)
{
  switch (slot) {
    case NPS_CTX_FACING_SONARS: return &ctx->facing_sonars;
    case NPS_CTX_TARGET_COPTER: return &ctx->target_copter;
    case NPS_CTX_BLOCKED: return &ctx->blocked;
    case NPS_CTX_WALL_DIST: return &ctx->wall_dist_m;
    case NPS_CTX_SPEED: return &ctx->speed_mps;
    case NPS_CTX_CROSSTALK_PATH: return &ctx->crosstalk_path_m;
    case NPS_CTX_TRIGGER_OFFSET: return &ctx->trigger_offset_s;
    case NPS_CTX_FLOOR: return &ctx->floor;
    case NPS_CTX_TARGET_OBSTACLE: return &ctx->target_obstacle;
    case NPS_CTX_VEHICLE: return &ctx->vehicle;
    default:
      return (slot >= NPS_CTX_EXTRA0 && slot < NPS_CTX_SLOTS) ? &ctx->extra[slot - NPS_CTX_EXTRA0] : NULL;
  }
}

int nps_sensor_ctx_slot_count(void)
{
  return NPS_CTX_SLOTS;
}

double nps_sensor_ctx_get(const struct nps_sensor_ctx *ctx, int slot)
{
  const double *p = ctx ? slot_ptr((struct nps_sensor_ctx *)ctx, slot) : NULL;
  return p ? *p : 0.0;
}

void nps_sensor_ctx_set(struct nps_sensor_ctx *ctx, int slot, double value)
{
  double *p = slot_ptr(ctx, slot);
  if (p) {
    *p = value;
  }
}

const char *nps_sensor_ctx_fixed_name(int slot)
{
  return (slot >= 0 && slot < NPS_CTX_EXTRA0) ? fixed_names[slot] : NULL;
}

/** The context slots an effect reads by itself, whatever its condition (nps_effect_apply in nps_effect.c). */
static bool effect_reads_slot(const struct nps_effect *e, int slot)
{
  if (e->kind == NPS_EFFECT_BIAS_CURVE) {
    return e->curve.over_slot == slot;
  }
  return e->kind == NPS_EFFECT_CROSSTALK &&
         (slot == NPS_CTX_FACING_SONARS || slot == NPS_CTX_CROSSTALK_PATH || slot == NPS_CTX_TRIGGER_OFFSET);
}

bool nps_sensor_chain_reads_ctx(const struct nps_sensor_chain *chain, int slot)
{
  for (size_t i = 0; chain != NULL && i < chain->n_effects; i++) {
    const struct nps_effect *e = &chain->effect[i];
    for (size_t t = 0; t < e->condition.n_terms; t++) {
      if (e->condition.term[t].slot == slot) {
        return true;
      }
    }
    if (effect_reads_slot(e, slot)) {
      return true;
    }
  }
  return false;
}

void nps_sensor_state_init(struct nps_sensor_state *state)
{
  state->newest = NPS_SENSOR_HISTORY_LEN - 1;
  state->count = 0;
}

void nps_sensor_state_push(struct nps_sensor_state *state, double t_s, double true_range_m)
{
  state->newest = (state->newest + 1) % NPS_SENSOR_HISTORY_LEN;
  state->t_s[state->newest] = t_s;
  state->true_range_m[state->newest] = true_range_m;
  if (state->count < NPS_SENSOR_HISTORY_LEN) {
    state->count++;
  }
}

double nps_sensor_state_true_range_at(const struct nps_sensor_state *state, double t_s)
{
  if (state->count == 0) {
    return NAN;
  }
  unsigned later = state->newest;
  for (unsigned n = 0; n < state->count; n++) {
    unsigned i = (state->newest + NPS_SENSOR_HISTORY_LEN - n) % NPS_SENSOR_HISTORY_LEN;
    if (state->t_s[i] <= t_s) {
      if (n == 0) {
        return state->true_range_m[i];
      }
      /* linear interpolation between entry i (at or before t_s) and the next one (after t_s) */
      double f = (t_s - state->t_s[i]) / (state->t_s[later] - state->t_s[i]);
      return state->true_range_m[i] + f * (state->true_range_m[later] - state->true_range_m[i]);
    }
    later = i;
  }
  return state->true_range_m[later];
}
