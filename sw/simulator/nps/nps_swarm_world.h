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
 * @file nps_swarm_world.h
 * Internal to nps_swarm*.c: the state behind nps_swarm.h.
 */

#ifndef NPS_SWARM_WORLD_H
#define NPS_SWARM_WORLD_H

#include "nps_swarm.h"
#include "nps_range_log.h"
#include "nps_raycast.h"

#include <gsl/gsl_rng.h>
#include <stdio.h>

/** Pings of one sonar remembered for cross-talk: a pulse may still be in flight after the next trigger. */
#define NPS_SWARM_PINGS 2

struct nps_swarm_vehicle {
  gsl_rng *sonar_rng[NPS_SONAR_COUNT];
  struct nps_sensor_state sonar_state[NPS_SONAR_COUNT];
  double ping_s[NPS_SONAR_COUNT][NPS_SWARM_PINGS];  ///< emission times of the last pulses [s], NAN: none
  unsigned ping_next[NPS_SONAR_COUNT];
  double pending_ping_s[NPS_SONAR_COUNT];  ///< pulse triggered this step, heard from the next one [s]
  unsigned pending_pings;                  ///< bit s set: pending_ping_s[s] holds a pulse
  double sonar_phase_s;     ///< this ring's shift against the simulated clock [s]
  double sonar_cycle_s;     ///< this ring's cycle (one pulse of each sonar) [s]
  double last_true_range_m[NPS_SONAR_COUNT];  ///< ground truth of each sonar's last reading [m]
  bool last_target_copter[NPS_SONAR_COUNT];   ///< whether that reading's first hit was a copter
  double speed_mps;
  /** pose given by nps_swarm_set_pose, taken at the next nps_swarm_step: while the copters' modules run,
   * every copter reads the poses of the step, whichever copter's flight model has already moved on */
  struct nps_swarm_pose {
    double pos_m[3], yaw_rad, speed_mps;
  } next_pose;
  gsl_rng *ranging_rng;
  bool ranging_equipped;
};

struct nps_swarm_world {
  uint64_t seed;
  unsigned n;
  unsigned first_id;                       ///< aircraft id of copter 0: copter v has id first_id + v ...
  unsigned max_id;                         ///< ... wrapped past max_id to 1 (0: never wrapped)
  struct nps_arena *arena;                 ///< owned by the walls hook (nps_walls_init)
  int *arena_index;                        ///< per copter: its index in arena->copters, -1 while absent
  double clock_offset_s;                   ///< added to every time given to this interface (nps_swarm_set_clock_offset)
  double last_step_s;                      ///< time given to the last nps_swarm_step (caller's clock) [s]
  bool walls_followed;                     ///< the walls' state is given (nps_swarm_follow_walls), not stepped here
  struct nps_swarm_vehicle *vehicles;
  struct nps_sensor_model *model;
  struct nps_range_log log;
  FILE *walls;
  const char *walls_path;
  double walls_period_s, next_walls_s;
  struct nps_sensor_state **ranging_state; ///< n x n, only when the ranging chain has a latency effect
  int *pushed;                             ///< per arena copter: 1 when the contacts of the last step moved it
  uint32_t ctx_needed[NPS_SENSOR_KINDS];   ///< bit slot set: a reading of that kind needs context slot `slot`
  bool ranging_disabled;                   ///< recorded ranging is replayed instead
  void (*before_read)(void);               ///< a shared world: bring the other copters to this step (nps_swarm_shared.c)
};

extern struct nps_swarm_world nps_swarm_world;

/** Whether a reading of `kind` needs context slot `slot`: the range log has every slot, a chain the slots it reads
 * (nps_sensor_chain_reads_ctx; worked out once, by nps_swarm_init). A slot nobody needs is left unset. */
static inline bool nps_swarm_needs_ctx(enum nps_sensor_kind kind, int slot)
{
  return (nps_swarm_world.ctx_needed[kind] >> slot) & 1u;
}

/** Copter v in the arena (it must be present: nps_swarm_set_present). */
static inline struct nps_arena_copter *nps_swarm_copter(unsigned v)
{
  return &nps_swarm_world.arena->copters[nps_swarm_world.arena_index[v]];
}

/** Aircraft id of copter v (its id in the arena, the logs and the random streams). */
static inline unsigned nps_swarm_id(unsigned v)
{
  const unsigned id = nps_swarm_world.first_id + v;
  return nps_swarm_world.max_id != 0 && id > nps_swarm_world.max_id ? id - nps_swarm_world.max_id : id;
}

/** The copter of aircraft id `id` (the inverse of nps_swarm_id). */
static inline unsigned nps_swarm_vehicle_of(unsigned id)
{
  return id >= nps_swarm_world.first_id ? id - nps_swarm_world.first_id : id + nps_swarm_world.max_id - nps_swarm_world.first_id;
}

#endif /* NPS_SWARM_WORLD_H */
