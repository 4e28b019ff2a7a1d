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
 * @file nps_swarm_shared.h
 * One arena for the NPS processes of a swarm (Paparazzi runs one NPS process per aircraft): this process's world
 * (nps_swarm.h) holds every aircraft id 1 .. NPS_WORLD_MAX_AIRCRAFT, its own aircraft as copter 0 (first_id its
 * id, max_id NPS_WORLD_MAX_AIRCRAFT), flown by its flight model; the others are the poses and pulses the other
 * processes publish (nps_world_link.h).
 *
 * Each step, at world time T (this process's simulated time plus the offset fixed when it joined):
 *  1. publish this copter's pose at T and the pulses its sonars sent since the last step;
 *  2. wait (asleep) until every other aircraft present has published up to T - sync window;
 *  3. take every other aircraft's pose at T: interpolated between its samples around T, or, when it is behind by
 *     at most the window, moved on from its newest sample at its last velocity (the age is counted); the pulses
 *     it published (world time: exact trigger times); whether it carries a ranging unit; who joined or left;
 *  4. the walls: the lowest aircraft id present steps them and publishes their state; every other process sets
 *     that state (one state for everyone, handed over when the owner leaves);
 *  5. nps_swarm_step.
 */

#ifndef NPS_SWARM_SHARED_H
#define NPS_SWARM_SHARED_H

#include "nps_world_link.h"

#ifdef __cplusplus
extern "C" {
#endif

struct nps_swarm_shared_config {
  const char *name;          ///< world name: the processes of one swarm share it
  const char *run;           ///< run id ("" or NULL: none); a live world of another run is refused
  unsigned ac_id;            ///< this process's aircraft
  double time_factor;        ///< simulated seconds per wall-clock second of every process of the world
  double peer_timeout_s;     ///< wall-clock seconds without news after which an aircraft has left
  double sync_window_s;      ///< how far behind T another aircraft may be before this one waits for it [s]
};

/** Consistency figures of this process's exchange. */
struct nps_swarm_shared_stats {
  unsigned long steps;
  unsigned long peer_poses;        ///< other aircraft's poses taken
  unsigned long extrapolated;      ///< of those, moved on from an older sample (the aircraft was behind)
  double age_max_s, age_sum_s;     ///< age of the poses taken (0 when interpolated) [s]
  double wait_s;                   ///< wall-clock time spent waiting for others [s]
  double exchange_s;               ///< wall-clock time of the whole exchange (publish, wait, read), waiting included [s]
};

/**
 * Join the world cfg->name. The swarm world must be set up with first_id cfg->ac_id and NPS_WORLD_MAX_AIRCRAFT
 * vehicles and max_id; every copter but this one (copter 0) is taken out of the arena until its aircraft publishes.
 * @param local_time_s  this process's simulated time now [s]
 * @return 0, or -1 with the reason in err
 */
extern int nps_swarm_share(const struct nps_swarm_shared_config *cfg, double local_time_s, char *err, size_t err_len);

/**
 * One step at this process's simulated time local_time_s, after nps_swarm_set_pose of its own copter: its pose and
 * pulses published; every NPS_SWARM_SHARED_MEET_EVERY steps a meeting (wait for the others, take them, above), then
 * nps_swarm_step (contacts, walls). A reading of other copters in between meets them at its own step first
 * (nps_swarm_set_before_read). @return 1 after a meeting with nps_swarm_step, 0 without, -1 as nps_swarm_step
 */
extern int nps_swarm_shared_step(double local_time_s);

/** World time minus this process's simulated time [s]. */
extern double nps_swarm_shared_offset_s(void);

/** Who joined or left since the last call, one line each; NULL when nothing happened. */
extern const char *nps_swarm_shared_news(void);

extern const struct nps_swarm_shared_stats *nps_swarm_shared_stats(void);

/** Leave the world (the last one out removes it). */
extern void nps_swarm_unshare(void);

#ifdef __cplusplus
}
#endif

#endif /* NPS_SWARM_SHARED_H */
