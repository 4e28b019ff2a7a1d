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
 * @file nps_swarm_shared.c
 * This process's part in a world shared by the NPS processes of a swarm (see nps_swarm_shared.h).
 */

#include "nps_swarm_shared.h"
#include "nps_swarm_world.h"
#include "nps_world_peer.h"

#include <math.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#ifndef NPS_SWARM_SHARED_MEET_EVERY
#define NPS_SWARM_SHARED_MEET_EVERY 8   ///< steps from one meeting for contacts and walls to the next
#endif

static struct {
  struct nps_world_link *link;
  unsigned own;                     ///< this aircraft's copter (0: its id comes first)
  double sync_window_s;
  bool owned_walls;                 ///< this process stepped the walls at the last meeting
  double step_s, step_local_s;      ///< world and local time of the current step
  double met_s;                     ///< world time of the last meeting (the others taken at it)
  unsigned steps_to_meeting;        ///< steps left before the next meeting for contacts and walls
  bool read_failed;                 ///< a meeting for a reading ran out of memory: the next step fails
  struct nps_world_peer peers[NPS_WORLD_MAX_AIRCRAFT];
  bool seen[NPS_WORLD_MAX_AIRCRAFT];  ///< per copter: among the peers this step
  struct nps_world_walls walls;
  struct nps_swarm_shared_stats stats;
} shared;

static void meet_for_reading(void);

static double wall_clock_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/** Identity of the arena's plates (FNV-1a over their count and rest endpoints): every process needs the same. */
static uint64_t arena_identity(const struct nps_arena *a)
{
  uint64_t h = 14695981039346656037u;
  const int count = a->num_segments;
  const unsigned char *bytes = (const unsigned char *)&count;
  for (size_t k = 0; k < sizeof(count); k++) {
    h = (h ^ bytes[k]) * 1099511628211u;
  }
  for (int i = 0; i < count; i++) {
    const double ends[4] = { a->segs[i].a[0], a->segs[i].a[1], a->segs[i].b[0], a->segs[i].b[1] };
    bytes = (const unsigned char *)ends;
    for (size_t k = 0; k < sizeof(ends); k++) {
      h = (h ^ bytes[k]) * 1099511628211u;
    }
  }
  return h;
}

int nps_swarm_share(const struct nps_swarm_shared_config *cfg, double local_time_s, char *err, size_t err_len)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  if (w->first_id != cfg->ac_id || w->n != NPS_WORLD_MAX_AIRCRAFT || w->max_id != NPS_WORLD_MAX_AIRCRAFT) {
    snprintf(err, err_len, "a shared world needs the swarm set up with this aircraft's id first and every id of "
             "1 .. %d", NPS_WORLD_MAX_AIRCRAFT);
    return -1;
  }
  const struct nps_world_link_config link_cfg = {
    .name = cfg->name, .run = cfg->run, .ac_id = cfg->ac_id, .time_factor = cfg->time_factor,
    .local_time_s = local_time_s, .arena_id = arena_identity(w->arena), .plates = (unsigned)w->arena->num_segments,
    .peer_timeout_s = cfg->peer_timeout_s,
  };
  memset(&shared, 0, sizeof(shared));
  if (nps_world_link_join(&link_cfg, &shared.link, err, err_len) < 0) {
    return -1;
  }
  shared.own = 0;
  shared.sync_window_s = cfg->sync_window_s;
  for (unsigned v = 0; v < w->n; v++) {
    if (v != shared.own && nps_swarm_set_present(v, false) < 0) {
      snprintf(err, err_len, "out of memory");
      nps_swarm_unshare();
      return -1;
    }
  }
  nps_swarm_set_clock_offset(nps_world_link_offset_s(shared.link));
  shared.met_s = NAN;
  nps_swarm_set_before_read(meet_for_reading);
  return 0;
}

/** This copter's pose at world time t_s and the pulses it sent since the last step, to the others. */
static void publish_own(double t_s)
{
  const struct nps_swarm_vehicle *veh = &nps_swarm_world.vehicles[shared.own];
  const struct nps_swarm_pose *p = &veh->next_pose;
  const struct nps_world_sample sample = {
    .t_s = t_s, .pos_m = { p->pos_m[0], p->pos_m[1], p->pos_m[2] }, .yaw_rad = p->yaw_rad, .speed_mps = p->speed_mps,
  };
  struct nps_world_ping pings[NPS_SONAR_COUNT];
  unsigned n = 0;
  for (unsigned s = 0; s < NPS_SONAR_COUNT; s++) {
    if (veh->pending_pings & (1u << s)) {
      pings[n++] = (struct nps_world_ping) { .t_s = veh->pending_ping_s[s], .sonar = s };
    }
  }
  nps_world_link_publish(shared.link, &sample, pings, n, veh->ranging_equipped);
}

/**
 * The last NPS_SWARM_PINGS pulses of each sonar the peer published, as its copter's pings: as in one process, where a
 * copter hears the pulses triggered up to the last step. Their times carry the peer's ring phase
 * (nps_swarm_sonar_attach), so they may lie after the reading: they are labels on the world clock, not events seen.
 */
static void take_pings(struct nps_swarm_vehicle *veh, const struct nps_world_peer *peer)
{
  for (unsigned s = 0; s < NPS_SONAR_COUNT; s++) {
    for (unsigned k = 0; k < NPS_SWARM_PINGS; k++) {
      veh->ping_s[s][k] = NAN;
    }
    veh->ping_next[s] = 0;
  }
  for (unsigned i = 0; i < peer->n_pings; i++) {   /* oldest first: the ring keeps the newest */
    const struct nps_world_ping *ping = &peer->pings[i];
    veh->ping_s[ping->sonar][veh->ping_next[ping->sonar]] = ping->t_s;
    veh->ping_next[ping->sonar] = (veh->ping_next[ping->sonar] + 1) % NPS_SWARM_PINGS;
  }
}

/** Every other aircraft as it is at world time t_s; who is present. */
static int take_peers(double t_s)
{
  struct nps_swarm_world *w = &nps_swarm_world;
  const unsigned n = nps_world_link_peers(shared.link, shared.peers, NPS_WORLD_MAX_AIRCRAFT, t_s);
  memset(shared.seen, 0, sizeof(shared.seen));
  for (unsigned k = 0; k < n; k++) {
    const struct nps_world_peer *peer = &shared.peers[k];
    const unsigned v = nps_swarm_vehicle_of(peer->ac_id);
    struct nps_world_sample pose;
    double age_s;
    if (nps_world_peer_pose_at(peer, t_s, shared.sync_window_s, &pose, &age_s) < 0) {
      continue;
    }
    nps_swarm_set_pose(v, pose.pos_m, pose.yaw_rad, pose.speed_mps);
    if (nps_swarm_set_present(v, true) < 0) {
      return -1;
    }
    take_pings(&w->vehicles[v], peer);
    w->vehicles[v].ranging_equipped = peer->ranging_equipped;
    shared.seen[v] = true;
    shared.stats.peer_poses++;
    shared.stats.extrapolated += age_s > 0.0;
    shared.stats.age_sum_s += age_s;
    shared.stats.age_max_s = fmax(shared.stats.age_max_s, age_s);
  }
  for (unsigned v = 0; v < w->n; v++) {
    if (v != shared.own && !shared.seen[v] && nps_swarm_set_present(v, false) < 0) {
      return -1;
    }
  }
  return 0;
}

/** Before the step: the owner steps the walls itself, every other process takes the owner's state. */
static int follow_or_own_walls(double local_time_s)
{
  shared.owned_walls = nps_world_link_owns_walls(shared.link);
  if (shared.owned_walls) {
    nps_swarm_step_walls();
    return 0;
  }
  struct nps_world_walls *walls = &shared.walls;
  if (nps_world_link_read_walls(shared.link, walls) < 0) {
    return 0;   /* nothing published yet, or unusable: the plates stay as they were */
  }
  return nps_swarm_follow_walls(walls->angle_rad, walls->rate_rad_s, walls->integral_deg_s, walls->n,
                                fmin(walls->t_s - nps_swarm_world.clock_offset_s, local_time_s));
}

/** After the step: the owner publishes the walls' state. */
static void publish_walls(void)
{
  const struct nps_arena *a = nps_swarm_world.arena;
  struct nps_world_walls *walls = &shared.walls;
  walls->t_s = a->time_s;
  walls->n = (unsigned)a->num_segments;
  for (int i = 0; i < a->num_segments; i++) {
    walls->angle_rad[i] = a->segs[i].angle_rad;
    walls->rate_rad_s[i] = a->segs[i].rate_rad_s;
    walls->integral_deg_s[i] = a->segs[i].integral_deg_s;
  }
  nps_world_link_publish_walls(shared.link, walls);
}

/** Meet the others at world time t_s: wait until they have published up to it, then take them and the walls. */
static int meet(double t_s, double local_time_s)
{
  const double started_s = wall_clock_s();
  nps_world_link_wait(shared.link, t_s - shared.sync_window_s);
  shared.stats.wait_s += wall_clock_s() - started_s;
  if (take_peers(t_s) < 0 || follow_or_own_walls(local_time_s) < 0) {
    return -1;
  }
  shared.met_s = t_s;
  shared.stats.exchange_s += wall_clock_s() - started_s;
  return 0;
}

/**
 * Before a reading of other copters (nps_swarm_before_read): the others at this step's time, unless this step met
 * them already, held apart as the contacts hold them (the flight model takes the correction at the next meeting of
 * nps_swarm_shared_step). Between meetings nothing else needs them, so a process waits only at the steps that read.
 */
static void meet_for_reading(void)
{
  if (shared.met_s == shared.step_s) {
    return;
  }
  if (meet(shared.step_s, shared.step_local_s) < 0 || nps_swarm_place_copters() < 0 ||
      nps_swarm_resolve_contacts() < 0) {
    shared.read_failed = true;
  }
}

int nps_swarm_shared_step(double local_time_s)
{
  const double t_s = local_time_s + nps_swarm_world.clock_offset_s;
  shared.step_s = t_s;
  shared.step_local_s = local_time_s;
  shared.stats.steps++;
  const double started_s = wall_clock_s();
  publish_own(t_s);
  nps_swarm_sonar_publish_pings();   /* the pulses of the last step are published: to the own ring */
  shared.stats.exchange_s += wall_clock_s() - started_s;
  if (shared.read_failed) {
    return -1;
  }
  if (shared.steps_to_meeting > 0) {
    shared.steps_to_meeting--;
    if (shared.owned_walls) {   /* the walls' owner steps them every step, as one process does (the others' poses
                                 * as at the last meeting) */
      if (nps_swarm_place_copters() < 0 || nps_swarm_walls_step(local_time_s) < 0) {
        return -1;
      }
      publish_walls();
    }
    return 0;
  }
  shared.steps_to_meeting = NPS_SWARM_SHARED_MEET_EVERY - 1;
  if (meet(t_s, local_time_s) < 0 || nps_swarm_step(local_time_s) < 0) {
    return -1;
  }
  if (shared.owned_walls) {
    publish_walls();
  }
  return 1;
}

double nps_swarm_shared_offset_s(void)
{
  return nps_world_link_offset_s(shared.link);
}

const char *nps_swarm_shared_news(void)
{
  return shared.link != NULL ? nps_world_link_news(shared.link) : NULL;
}

const struct nps_swarm_shared_stats *nps_swarm_shared_stats(void)
{
  return &shared.stats;
}

void nps_swarm_unshare(void)
{
  nps_swarm_set_before_read(NULL);
  nps_world_link_leave(shared.link);
  shared.link = NULL;
}
