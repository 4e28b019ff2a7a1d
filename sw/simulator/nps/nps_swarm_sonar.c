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
 * @file nps_swarm_sonar.c
 * Simulated FINken sonar ring: ray cast, cross-talk from the pulses in flight, sensor model, range log.
 */

#include "nps_swarm_world.h"
#include "nps_crosstalk.h"
#include "nps_sensor_model.h"

#include <math.h>
#include <gsl/gsl_rng.h>

/** Ray length for the ground truth: beyond any arena, so true ranges past the sensor's maximum are known [m]. */
#define NPS_SWARM_SONAR_TRUTH_RANGE_M 100.0
/** Facing emitters examined per reading (nearest first). */
#define NPS_SWARM_SONAR_MAX_FACING 8

void nps_swarm_sonar_attach(unsigned v, double cycle_s)
{
  struct nps_swarm_vehicle *veh = &nps_swarm_world.vehicles[v];
  veh->sonar_phase_s = cycle_s * gsl_rng_uniform(veh->sonar_rng[NPS_SONAR_FRONT]);
  veh->sonar_cycle_s = cycle_s;
}

/**
 * The world-clock label of a ring event at local time time_s. The ring runs on the local clock, whose offset to the
 * world clock is wherever the process joined the world; only the offset's whole cycles are added, so every ring
 * keeps its seeded phase on the world clock, as in one process, and two rings' trigger offset (hence their
 * cross-talk) is the seed's, not the processes' start times'.
 */
static double ring_time_s(const struct nps_swarm_vehicle *veh, double time_s)
{
  const double offset_s = nps_swarm_world.clock_offset_s;
  const double whole_cycles_s = veh->sonar_cycle_s > 0.0 ? offset_s - fmod(offset_s, veh->sonar_cycle_s) : offset_s;
  return time_s + whole_cycles_s + veh->sonar_phase_s;
}

void nps_swarm_sonar_trigger(unsigned v, unsigned sonar, double time_s)
{
  struct nps_swarm_vehicle *veh = &nps_swarm_world.vehicles[v];
  veh->pending_ping_s[sonar] = ring_time_s(veh, time_s);
  veh->pending_pings |= 1u << sonar;
}

void nps_swarm_sonar_publish_pings(void)
{
  for (unsigned v = 0; v < nps_swarm_world.n; v++) {
    struct nps_swarm_vehicle *veh = &nps_swarm_world.vehicles[v];
    /* the set bits only, lowest sonar first (a local mask: the stores below cannot touch it) */
    for (unsigned pending = veh->pending_pings; pending != 0; pending &= pending - 1) {
      const unsigned s = (unsigned)__builtin_ctz(pending);
      veh->ping_s[s][veh->ping_next[s]] = veh->pending_ping_s[s];
      veh->ping_next[s] = (veh->ping_next[s] + 1) % NPS_SWARM_PINGS;
    }
    veh->pending_pings = 0;
  }
}

/**
 * Whether a facing emitter's pulse (of its last NPS_SWARM_PINGS) arrives in the window (nps_crosstalk_heard, the
 * travel time worked out once); its offset in *offset_s.
 */
static bool pulse_heard(const struct nps_swarm_vehicle *em, const struct nps_facing_sonar *f, double listen_s,
                        double window_s, double speed_of_sound_mps, double *offset_s)
{
  const double travel_s = f->path_m / speed_of_sound_mps;
  for (unsigned k = 0; k < NPS_SWARM_PINGS; k++) {
    *offset_s = em->ping_s[f->sonar][k] - listen_s;
    if (!isnan(*offset_s) && nps_crosstalk_arrives(travel_s, *offset_s, window_s)) {
      return true;
    }
  }
  return false;
}

/**
 * Of the other copters' sonars that face this one (each in the other's beam cone and range) with a clear
 * path, those whose pulse arrives within [listen_s, listen_s + window_s]: how many, and the nearest one's
 * path and trigger offset (nps_crosstalk.h). The line of sight, a ray cast, is only tested for the pulses
 * heard.
 */
static void heard_emitters(const struct nps_arena_copter *rx, const double p_r[3], const double b_r[3],
                           double listen_s, double window_s, double range_m, double speed_of_sound_mps,
                           struct nps_sensor_ctx *ctx)
{
  const struct nps_swarm_world *w = &nps_swarm_world;
  struct nps_facing_sonar facing[NPS_SWARM_SONAR_MAX_FACING];
  const int n = nps_raycast_facing_nearest(w->arena, rx->id, p_r, b_r, w->arena->sonar_cos_half_angle, range_m,
                                           facing, NPS_SWARM_SONAR_MAX_FACING);
  for (int i = 0; i < n && i < NPS_SWARM_SONAR_MAX_FACING; i++) {
    const struct nps_facing_sonar *f = &facing[i];
    double offset_s;
    const struct nps_swarm_vehicle *emitter = &w->vehicles[nps_swarm_vehicle_of((unsigned)f->copter_id)];
    if (pulse_heard(emitter, f, listen_s, window_s, speed_of_sound_mps, &offset_s) &&
        !nps_raycast_line_blocked(w->arena, f->emitter_pos_m, p_r, f->copter_id, rx->id, NULL)) {
      if (ctx->facing_sonars == 0.0) {   /* nearest first: keep the first one heard */
        ctx->crosstalk_path_m = f->path_m;
        ctx->trigger_offset_s = offset_s;
      }
      ctx->facing_sonars += 1.0;
    }
  }
}

double nps_swarm_sonar_read(unsigned v, unsigned sonar, double fired_s, double now_s)
{
  const struct nps_swarm_world *w = &nps_swarm_world;
  if (w->before_read != NULL) {
    w->before_read();
  }
  struct nps_swarm_vehicle *veh = &w->vehicles[v];
  const double ring_fired_s = ring_time_s(veh, fired_s);
  const double listened_s = now_s - fired_s;
  now_s += w->clock_offset_s;
  const struct nps_sensor_chain *chain = nps_sensor_model_chain_of(w->model, NPS_SENSOR_SONAR);
  const struct nps_arena_copter *c = nps_swarm_copter(v);

  double p_r[3], b_r[3];
  struct nps_ray_hit hit;
  nps_raycast_sonar_pose(w->arena, c, (enum nps_sonar)sonar, p_r, b_r);
  nps_raycast_range(w->arena, p_r, b_r, NPS_SWARM_SONAR_TRUTH_RANGE_M, c->id, NPS_RAYCAST_NO_ID, &hit);
  const double true_range_m = hit.kind == NPS_HIT_NOTHING ? NPS_SWARM_SONAR_TRUTH_RANGE_M : hit.range_m;

  /* a copy of a zero struct (stores of zeroed registers), not a partly named initialiser (`rep stos`, slow to start) */
  static const struct nps_sensor_ctx no_ctx;
  struct nps_sensor_ctx ctx = no_ctx;
  ctx.target_copter = hit.kind == NPS_HIT_COPTER;
  ctx.target_obstacle = hit.kind == NPS_HIT_OBSTACLE;
  ctx.vehicle = nps_swarm_id(v);
  ctx.wall_dist_m = nps_swarm_needs_ctx(NPS_SENSOR_SONAR, NPS_CTX_WALL_DIST) ? nps_raycast_wall_dist(w->arena, c->pos_m)
                    : 0.0;
  ctx.speed_mps = veh->speed_mps;
  if (sonar == NPS_SONAR_DOWN && nps_swarm_needs_ctx(NPS_SENSOR_SONAR, NPS_CTX_FLOOR)) {
    ctx.floor = nps_floor_material_at(&w->arena->floor, c->pos_m[0], c->pos_m[1]);
  }
  /* the context of cross-talk (the count, the nearest path and offset) comes from one search */
  const uint32_t crosstalk_ctx = 1u << NPS_CTX_FACING_SONARS | 1u << NPS_CTX_CROSSTALK_PATH | 1u << NPS_CTX_TRIGGER_OFFSET;
  if (chain != NULL && (w->ctx_needed[NPS_SENSOR_SONAR] & crosstalk_ctx) != 0) {
    heard_emitters(c, p_r, b_r, ring_fired_s, listened_s, chain->max_range_m,
                   chain->speed_of_sound_mps, &ctx);
  }
  struct nps_sensor_state *state = chain != NULL && nps_sensor_chain_reads_state(chain) ? &veh->sonar_state[sonar]
                                   : NULL;
  const double measured_m = chain != NULL
                            ? nps_sensor_chain_apply(chain, now_s, true_range_m, &ctx, state, veh->sonar_rng[sonar])
                            : true_range_m;
  if (nps_range_log_is_open(&w->log)) {   /* not even the sensor's name without a log (--no-logs) */
    nps_range_log_write(&nps_swarm_world.log, now_s, nps_swarm_id(v), nps_sonar_name((enum nps_sonar)sonar), -1, true_range_m,
                        measured_m, &ctx);
  }
  veh->last_true_range_m[sonar] = true_range_m;
  veh->last_target_copter[sonar] = ctx.target_copter != 0.0;
  return measured_m;
}

void nps_swarm_sonar_last_truth(unsigned v, unsigned sonar, double *true_range_m, bool *target_copter)
{
  const struct nps_swarm_vehicle *veh = &nps_swarm_world.vehicles[v];
  *true_range_m = veh->last_true_range_m[sonar];
  *target_copter = veh->last_target_copter[sonar];
}
