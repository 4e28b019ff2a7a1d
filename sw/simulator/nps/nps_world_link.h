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
 * @file nps_world_link.h
 * The exchange between the NPS processes of one swarm (one process per aircraft): the transport behind one small
 * interface. Today: POSIX shared memory on one machine (nps_world_link_shm.c); a network transport would implement
 * the same functions (docs/paparazzi.md, "Beyond one machine").
 *
 * What crosses: each aircraft's pose samples (world time, ENU position, yaw, speed) and its sonar pulses (world time
 * and sonar), whether it carries a ranging unit, and the curtain walls' plate angles from the one aircraft that
 * steps them (the lowest aircraft id present). Every aircraft computes its own sensors from these.
 *
 * World time: the simulated seconds of the world, common to all processes: each process maps its own simulated time
 * to it by an offset fixed when it joins (nps_world_link_offset_s). Every time given to or read from this interface
 * is world time.
 */

#ifndef NPS_WORLD_LINK_H
#define NPS_WORLD_LINK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Aircraft ids of a world: 1 .. NPS_WORLD_MAX_AIRCRAFT. */
#define NPS_WORLD_MAX_AIRCRAFT 64
/** Pose samples kept per aircraft (at 512 Hz: the last 125 ms). */
#define NPS_WORLD_SAMPLES 64
/** Sonar pulses kept per aircraft (5 sonars fire 100 pulses/s: the last 320 ms). */
#define NPS_WORLD_PINGS 32
/** Plates of the curtain walls a world can share. */
#define NPS_WORLD_MAX_PLATES 1024

/** One pose sample of an aircraft. */
struct nps_world_sample {
  double t_s;          ///< world time [s]
  double pos_m[3];     ///< arena frame, ENU [m]
  double yaw_rad;      ///< from x toward y [rad]
  double speed_mps;    ///< horizontal speed [m/s]
};

/** One sonar pulse. */
struct nps_world_ping {
  double t_s;          ///< world time of emission [s]
  uint32_t sonar;      ///< nps_sonar index
};

/** What a process reads of one other aircraft: a consistent copy (never torn), newest sample last. */
struct nps_world_peer {
  unsigned ac_id;
  bool ranging_equipped;
  unsigned n_samples;                                ///< valid entries of samples, oldest first
  struct nps_world_sample samples[NPS_WORLD_SAMPLES];
  unsigned n_pings;                                  ///< valid entries of pings, oldest first
  struct nps_world_ping pings[NPS_WORLD_PINGS];
};

/** Plate state the walls' owner publishes. */
struct nps_world_walls {
  double t_s;                                  ///< world time of the state [s]
  unsigned owner_id;                           ///< aircraft that stepped it
  unsigned n;                                  ///< plates
  double angle_rad[NPS_WORLD_MAX_PLATES];
  double rate_rad_s[NPS_WORLD_MAX_PLATES];
  double integral_deg_s[NPS_WORLD_MAX_PLATES];   ///< PID integral (a new owner goes on from it)
};

struct nps_world_link;

/** How a process joins. */
struct nps_world_link_config {
  const char *name;           ///< world name (FINKEN_WORLD): processes with the same name share one world
  const char *run;            ///< run id (FINKEN_WORLD_RUN, "" for none): a live world of another run is refused
  unsigned ac_id;             ///< this aircraft, 1 .. NPS_WORLD_MAX_AIRCRAFT
  double time_factor;         ///< simulated seconds per wall-clock second of this process (NPS --time_factor)
  double local_time_s;        ///< this process's simulated time now [s]
  uint64_t arena_id;          ///< identity of arena and plate count: every process of a world must have the same
  unsigned plates;            ///< plates of the arena's curtain walls (<= NPS_WORLD_MAX_PLATES)
  double peer_timeout_s;      ///< wall-clock seconds without news after which a peer has left the world
};

/**
 * Join (creating it if needed) the world cfg->name as aircraft cfg->ac_id. A stale world (its processes gone) is
 * reclaimed; a live world of another run, of another arena or time factor, or with this aircraft id taken, is refused.
 * @return 0, or -1 with the reason in err (naming the world and what to do)
 */
extern int nps_world_link_join(const struct nps_world_link_config *cfg, struct nps_world_link **link, char *err,
                               size_t err_len);
/** Leave the world (the last one out removes it); NULL is ignored. */
extern void nps_world_link_leave(struct nps_world_link *link);

/** World time minus this process's simulated time [s] (fixed when joining). */
extern double nps_world_link_offset_s(const struct nps_world_link *link);
/** Whether this process created the world or reclaimed a stale one (for the log). */
extern bool nps_world_link_created(const struct nps_world_link *link);

/** Publish this aircraft's pose sample, the pulses it sent since the last call, and its ranging unit. */
extern void nps_world_link_publish(struct nps_world_link *link, const struct nps_world_sample *sample,
                                   const struct nps_world_ping *pings, unsigned n_pings, bool ranging_equipped);

/**
 * Wait (sleeping, never spinning) until every other aircraft present has published a sample at or after t_s, or
 * has left: its process ended or sent nothing for peer_timeout_s of wall-clock time.
 */
extern void nps_world_link_wait(struct nps_world_link *link, double t_s);
/**
 * How many times nps_world_link_wait of this link went to sleep in the kernel (and was woken or timed out), for the
 * tests: waiting sleeps, never spins. Any thread may read it while another waits.
 */
extern uint64_t nps_world_link_sleeps(const struct nps_world_link *link);

/**
 * The other aircraft present, by id: peers[k] for k < return value, each with the samples a pose at world time t_s
 * needs (nps_world_peer_pose_at): from its newest back to the newest at or before t_s, at least two (all of the
 * ring for t_s = -inf), and its last pulses. An aircraft that left, or whose shared data cannot be read
 * consistently, is not among them.
 */
extern unsigned nps_world_link_peers(struct nps_world_link *link, struct nps_world_peer *peers, unsigned max,
                                     double t_s);

/** Whether this aircraft owns the walls: the lowest id present steps them and publishes their state. */
extern bool nps_world_link_owns_walls(struct nps_world_link *link);
/** The owner publishes the plate state. */
extern void nps_world_link_publish_walls(struct nps_world_link *link, const struct nps_world_walls *walls);
/** The last plate state published (0), or -1 when none is (yet) readable. */
extern int nps_world_link_read_walls(struct nps_world_link *link, struct nps_world_walls *walls);

/** One line per aircraft that joined or left the world since the last call (for the process's log); NULL when none. */
extern const char *nps_world_link_news(struct nps_world_link *link);

#ifdef __cplusplus
}
#endif

#endif /* NPS_WORLD_LINK_H */
