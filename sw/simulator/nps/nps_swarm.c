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
 * @file nps_swarm.c
 * The world the NPS sensor simulations share: set-up, poses, steps (see nps_swarm.h).
 */

#include "nps_swarm_world.h"
#include "nps_arena_contact.h"
#include "nps_error.h"
#include "nps_arena_snapshot.h"
#include "nps_rng.h"
#include "nps_walls.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

struct nps_swarm_world nps_swarm_world;

/** Set-up failed: the reason in err, and nothing of the half-built world left. */
static int fail(char *err, size_t err_len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(char *err, size_t err_len, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  nps_error_vset(err, err_len, fmt, ap);
  va_end(ap);
  nps_swarm_free();
  return -1;
}

/** Put the n copters (ids nps_swarm_id(0 .. n - 1), the arena's body size) into the arena; their poses come with set_pose. */
static int place_copters(struct nps_swarm_world *w)
{
  struct nps_arena_copter *start = malloc(w->n * sizeof(*start));
  if (start == NULL) {
    return -1;
  }
  for (unsigned v = 0; v < w->n; v++) {
    start[v] = nps_arena_copter_make(w->arena, (int)nps_swarm_id(v), 0.0, 0.0, w->arena->flight_height_m, 0.0);
    w->arena_index[v] = (int)v;
  }
  const int rc = nps_walls_set_copters(start, (int)w->n);
  free(start);
  for (unsigned v = 0; rc == 0 && v < w->n; v++) {
    const struct nps_arena_copter *c = nps_swarm_copter(v);
    w->vehicles[v].next_pose = (struct nps_swarm_pose) { { c->pos_m[0], c->pos_m[1], c->pos_m[2] }, c->yaw_rad, 0.0 };
  }
  return rc;
}

/** The context slots a reading of each kind needs (nps_swarm_needs_ctx), once the log is open or not. */
static void find_ctx_needed(struct nps_swarm_world *w)
{
  for (int kind = 0; kind < NPS_SENSOR_KINDS; kind++) {
    const struct nps_sensor_chain *chain = nps_sensor_model_chain_of(w->model, (enum nps_sensor_kind)kind);
    w->ctx_needed[kind] = 0;
    for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
      if (nps_range_log_is_open(&w->log) || nps_sensor_chain_reads_ctx(chain, slot)) {
        w->ctx_needed[kind] |= 1u << slot;
      }
    }
  }
}

int nps_swarm_init(const struct nps_swarm_config *cfg, char *err, size_t err_len)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  nps_swarm_free();
  w->seed = cfg->seed;
  w->n = cfg->vehicles;
  w->first_id = cfg->first_id != 0 ? cfg->first_id : 1;
  w->max_id = cfg->max_id;
  if (w->max_id != 0 && (w->first_id > w->max_id || w->n > w->max_id)) {
    return fail(err, err_len, "aircraft id %u and %u copters do not fit ids 1 .. %u", w->first_id, w->n, w->max_id);
  }
  if (nps_walls_init(cfg->arena_file) < 0) {
    return fail(err, err_len, "%s", nps_walls_error());
  }
  w->arena = nps_walls_arena();
  if (nps_sensor_model_from_define(cfg->sensor_model, "NPS_SENSOR_MODEL", &w->model, err, err_len) < 0) {
    nps_swarm_free();
    return -1;
  }
  w->vehicles = calloc(w->n, sizeof(*w->vehicles));
  w->pushed = calloc(w->n, sizeof(*w->pushed));
  w->arena_index = calloc(w->n, sizeof(*w->arena_index));
  if (w->vehicles == NULL || w->pushed == NULL || w->arena_index == NULL || place_copters(w) < 0) {
    return fail(err, err_len, "out of memory for %u copters", w->n);
  }
  const struct nps_sensor_chain *ranging = nps_sensor_model_chain_of(w->model, NPS_SENSOR_RANGING);
  if (ranging != NULL && nps_sensor_chain_reads_state(ranging)) {
    w->ranging_state = calloc((size_t)w->n * w->n, sizeof(*w->ranging_state));
    if (w->ranging_state == NULL) {
      return fail(err, err_len, "out of memory for the ranging latency of %u copters", w->n);
    }
  }
  for (unsigned v = 0; v < w->n; v++) {
    struct nps_swarm_vehicle *veh = &w->vehicles[v];
    for (unsigned s = 0; s < NPS_SONAR_COUNT; s++) {
      veh->sonar_rng[s] = nps_rng_stream_new(w->seed, nps_swarm_id(v), NPS_RNG_SENSOR_SONAR_FRONT + s);
      nps_sensor_state_init(&veh->sonar_state[s]);
      for (unsigned k = 0; k < NPS_SWARM_PINGS; k++) {
        veh->ping_s[s][k] = NAN;
      }
    }
    veh->ranging_rng = nps_rng_stream_new(w->seed, nps_swarm_id(v), NPS_RNG_SENSOR_RANGING_BASE);
    if (veh->ranging_rng == NULL || veh->sonar_rng[NPS_SONAR_COUNT - 1] == NULL) {
      return fail(err, err_len, "out of memory for the random streams of %u copters", w->n);
    }
  }
  if (cfg->readings_path != NULL && nps_range_log_open(&w->log, cfg->readings_path) < 0) {
    return fail(err, err_len, "cannot write %s: %s", cfg->readings_path, strerror(errno));
  }
  find_ctx_needed(w);
  if (cfg->walls_path != NULL) {
    w->walls = fopen(cfg->walls_path, "w");
    if (w->walls == NULL) {
      return fail(err, err_len, "cannot write %s: %s", cfg->walls_path, strerror(errno));
    }
    nps_arena_snapshot_header(w->walls);
    w->walls_path = cfg->walls_path;
    w->walls_period_s = cfg->walls_period_s;
    w->next_walls_s = 0.0;
  }
  return 0;
}

int nps_swarm_free(void)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  int rc = nps_range_log_close(&w->log);
  if (w->walls != NULL && (ferror(w->walls) | fclose(w->walls)) != 0) {
    rc = -1;
  }
  for (unsigned v = 0; w->vehicles != NULL && v < w->n; v++) {
    for (unsigned s = 0; s < NPS_SONAR_COUNT; s++) {
      gsl_rng_free(w->vehicles[v].sonar_rng[s]);
    }
    gsl_rng_free(w->vehicles[v].ranging_rng);
  }
  for (size_t i = 0; w->ranging_state != NULL && i < (size_t)w->n * w->n; i++) {
    free(w->ranging_state[i]);
  }
  free(w->ranging_state);
  free(w->pushed);
  free(w->arena_index);
  free(w->vehicles);
  nps_sensor_model_free(w->model);
  nps_walls_free();
  memset(w, 0, sizeof(*w));
  return rc;
}

const char *nps_swarm_write_error(void)
{
  const struct nps_swarm_world *w = &nps_swarm_world;
  if (w->log.file != NULL && ferror(w->log.file)) {
    return w->log.path;
  }
  return w->walls != NULL && ferror(w->walls) ? w->walls_path : NULL;
}

void nps_swarm_get_position(unsigned v, double pos_m[3])
{
  memcpy(pos_m, nps_swarm_copter(v)->pos_m, 3 * sizeof(double));
}

bool nps_swarm_pushed(unsigned v)
{
  return nps_swarm_world.pushed[nps_swarm_world.arena_index[v]] != 0;
}

bool nps_swarm_present(unsigned v)
{
  return nps_swarm_world.arena_index[v] >= 0;
}

int nps_swarm_set_present(unsigned v, bool present)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  if (nps_swarm_present(v) == present) {
    return 0;
  }
  /* the arena's copters again, in copter order, with v added (at the pose it was last given) or left out */
  struct nps_arena_copter *list = malloc(w->n * sizeof(*list));
  int *index = malloc(w->n * sizeof(*index));
  if (list == NULL || index == NULL) {
    free(list);
    free(index);
    return -1;
  }
  int k = 0;
  for (unsigned u = 0; u < w->n; u++) {
    index[u] = -1;
    if (u == v && present) {
      const struct nps_swarm_pose *p = &w->vehicles[v].next_pose;
      list[k] = nps_arena_copter_make(w->arena, (int)nps_swarm_id(v), p->pos_m[0], p->pos_m[1], p->pos_m[2],
                                      p->yaw_rad);
      index[u] = k++;
    } else if (u != v && nps_swarm_present(u)) {
      list[k] = *nps_swarm_copter(u);
      index[u] = k++;
    }
  }
  const int rc = nps_walls_set_copters(list, k);
  if (rc == 0) {
    memcpy(w->arena_index, index, w->n * sizeof(*index));
    memset(w->pushed, 0, w->n * sizeof(*w->pushed));
  }
  if (!present) {   /* a copter that left sends no more pulses */
    for (unsigned s = 0; s < NPS_SONAR_COUNT; s++) {
      for (unsigned i = 0; i < NPS_SWARM_PINGS; i++) {
        w->vehicles[v].ping_s[s][i] = NAN;
      }
    }
    w->vehicles[v].pending_pings = 0;
    w->vehicles[v].ranging_equipped = false;
  }
  free(list);
  free(index);
  return rc;
}

void nps_swarm_set_clock_offset(double offset_s)
{
  nps_swarm_world.clock_offset_s = offset_s;
}

int nps_swarm_follow_walls(const double *angle_rad, const double *rate_rad_s, const double *integral_deg_s,
                           unsigned plates, double time_s)
{
  nps_swarm_world.walls_followed = true;
  return nps_arena_walls_set_state(nps_swarm_world.arena, time_s + nps_swarm_world.clock_offset_s, angle_rad,
                                   rate_rad_s, integral_deg_s, (int)plates);
}

void nps_swarm_step_walls(void)
{
  nps_swarm_world.walls_followed = false;
}

const struct nps_arena *nps_swarm_arena(void)
{
  return nps_swarm_world.arena;
}

void nps_swarm_set_pose(unsigned v, const double pos_m[3], double yaw_rad, double speed_mps)
{
  nps_swarm_world.vehicles[v].next_pose = (struct nps_swarm_pose) { { pos_m[0], pos_m[1], pos_m[2] }, yaw_rad, speed_mps };
}

bool nps_swarm_needs_speed(void)
{
  for (int kind = 0; kind < NPS_SENSOR_KINDS; kind++) {
    if (nps_swarm_needs_ctx((enum nps_sensor_kind)kind, NPS_CTX_SPEED)) {
      return true;
    }
  }
  return false;
}

/** Every copter takes the pose it was given last (nps_swarm_set_pose). */
static void take_poses(struct nps_swarm_world *w)
{
  for (unsigned v = 0; v < w->n; v++) {
    if (!nps_swarm_present(v)) {
      continue;
    }
    const struct nps_swarm_pose *p = &w->vehicles[v].next_pose;
    struct nps_arena_copter *c = nps_swarm_copter(v);
    memcpy(c->pos_m, p->pos_m, sizeof(c->pos_m));
    c->yaw_rad = p->yaw_rad;
    w->vehicles[v].speed_mps = p->speed_mps;
  }
}

int nps_swarm_place_copters(void)
{
  take_poses(&nps_swarm_world);
  return nps_arena_poses_moved(nps_swarm_world.arena);
}

void nps_swarm_set_before_read(void (*hook)(void))
{
  nps_swarm_world.before_read = hook;
}

int nps_swarm_effect_param(const char *kind, const char *effect, const char *param, double *value, bool set)
{
  const int k = nps_sensor_kind_from_name(kind);
  if (nps_swarm_world.model == NULL || k < 0 || !nps_swarm_world.model->has_chain[k]) {
    return -1;
  }
  struct nps_sensor_chain *chain = &nps_swarm_world.model->chain[k];
  for (size_t i = 0; i < chain->n_effects; i++) {
    struct nps_effect *e = &chain->effect[i];
    if (strcmp(nps_effect_name(e->kind), effect) == 0) {
      const int j = nps_effect_param_index(e->kind, param);
      if (j < 0) {
        return -1;
      }
      if (!set) {
        *value = e->param[j];
        return 0;
      }
      return nps_effect_set_param(e, (size_t)j, *value);
    }
  }
  return -1;
}

double nps_swarm_usec_to_s(uint32_t usec)
{
  const double wrap_s = 4294.967296;   /* 2^32 us */
  const double t_s = usec * 1e-6;
  return t_s + wrap_s * nearbyint((nps_swarm_world.last_step_s - t_s) / wrap_s);
}

int nps_swarm_step(double time_s)
{
  nps_swarm_world.last_step_s = time_s;
  nps_swarm_sonar_publish_pings();
  if (nps_swarm_place_copters() < 0 || nps_swarm_resolve_contacts() < 0) {
    return -1;
  }
  return nps_swarm_walls_step(time_s);
}

int nps_swarm_resolve_contacts(void)
{
  return nps_arena_resolve_contacts(nps_swarm_world.arena, nps_swarm_world.pushed) < 0 ? -1 : 0;
}

int nps_swarm_walls_step(double time_s)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  time_s += w->clock_offset_s;
  if (!w->walls_followed) {
    nps_walls_run_step(time_s);
  }
  if (w->walls != NULL && !w->walls_followed && time_s >= w->next_walls_s) {   /* the walls' owner logs them */
    nps_arena_snapshot_write(w->arena, w->walls);
    w->next_walls_s += w->walls_period_s;
    if (w->next_walls_s <= time_s) {   /* taken over from another owner: the next row a period from now */
      w->next_walls_s = time_s + w->walls_period_s;
    }
  }
  return 0;
}
