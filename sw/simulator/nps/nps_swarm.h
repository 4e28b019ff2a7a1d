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
 * @file nps_swarm.h
 * The world the NPS sensor simulations of every copter share: the arena and its walls, where each copter
 * is, the sensor model, each copter's random streams, the sonar pings in flight, and the range log.
 * One per simulator process, like NPS's flight model.
 *
 * The host (sim/) sets it up, gives every copter's pose each step and advances it; the NPS variants of the
 * modules (sw/airborne/arch/sim) trigger and read sonars and measure ranging distances through it.
 * Copter v (0 .. n-1) has aircraft id v + 1.
 */

#ifndef NPS_SWARM_H
#define NPS_SWARM_H

#include "nps_arena.h"
#include "nps_sensor_model.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct nps_swarm_config {
  uint64_t seed;               ///< seed of every random stream
  unsigned vehicles;           ///< number of copters
  unsigned first_id;           ///< aircraft id of copter 0, the others follow (0: 1); ids seed the random streams
  unsigned max_id;             ///< ids past it wrap around to 1, so that copter 0 may be any id of 1 .. max_id
                               ///< with vehicles = max_id (0: no wrap)
  const char *arena_file;      ///< arena XML (conf/arena/...)
  const char *sensor_model;    ///< model file or inline model text (nps_sensor_model_from_define)
  const char *readings_path;   ///< range log to write, NULL for none
  const char *walls_path;      ///< wall snapshots to write, NULL for none
  double walls_period_s;       ///< time between two wall snapshots [s]
};

/** Set up the world; -1 with the reason ("file:line: reason") in err. Replaces a previous world. */
extern int nps_swarm_init(const struct nps_swarm_config *cfg, char *err, size_t err_len);
/** Close the logs and free everything; -1 with errno set if a log could not be written. */
extern int nps_swarm_free(void);
/** The path of a log that failed to be written so far (range log or walls), NULL while every write succeeded. */
extern const char *nps_swarm_write_error(void);

/**
 * Seconds of a microsecond clock that wraps every 2^32 us (Paparazzi's get_sys_time_usec, 71.6 min): the time
 * closest to the last nps_swarm_step's, so that times run on over the wraps. Give the simulator these, not usec * 1e-6.
 */
extern double nps_swarm_usec_to_s(uint32_t usec);

/** The arena (for initial positions, plots and tests). */
extern const struct nps_arena *nps_swarm_arena(void);
/**
 * Give copter v's pose: ENU position [m], yaw from x toward y [rad], horizontal speed [m/s]. The copter takes
 * it at the next nps_swarm_step: until then the sensors still see the pose of the current step, so copters
 * whose flight models move on while the others still read their sensors (threads) change nothing.
 */
extern void nps_swarm_set_pose(unsigned v, const double pos_m[3], double yaw_rad, double speed_mps);
/**
 * Whether any reading uses the speeds given to nps_swarm_set_pose (a chain reads ctx_speed, or the range log is
 * open): if not, nothing reads them, and a host may pass 0 instead of working them out.
 */
extern bool nps_swarm_needs_speed(void);
/**
 * After every copter's pose: take the poses, publish the sonar pulses of the last step, index the copters, resolve contacts
 * (bodies apart, copters inside the walls: nps_arena_contact.h), advance the walls to time_s, write a wall
 * snapshot when due.
 */
extern int nps_swarm_step(double time_s);
/**
 * The walls' part of nps_swarm_step alone: stepped to time_s (this process's clock) and logged, unless they are
 * followed (nps_swarm_follow_walls). @return 0
 */
extern int nps_swarm_walls_step(double time_s);
/**
 * Put every present copter at its pose given by nps_swarm_set_pose (as nps_swarm_step does first), without contacts
 * or walls: for a reading between two steps of the arena. @return 0, or -1 on ENOMEM
 */
extern int nps_swarm_place_copters(void);
/** The contacts of the copters where they are placed (nps_swarm_pushed tells who moved). @return 0, or -1 on ENOMEM */
extern int nps_swarm_resolve_contacts(void);
/** A function every reading of another copter (sonar, ranging) calls first; NULL: none (nps_swarm_shared.c sets it). */
extern void nps_swarm_set_before_read(void (*hook)(void));
/** Copter v's position after the contacts of the last step [m]. */
extern void nps_swarm_get_position(unsigned v, double pos_m[3]);
/**
 * Whether the contacts of the last step moved copter v (possibly by less than a rounding step): if not, its position
 * is exactly the one given to nps_swarm_set_pose before that step.
 */
extern bool nps_swarm_pushed(unsigned v);

/**
 * Read (set = false) or change (set = true) parameter `param` of the first effect named `effect` in the
 * `kind` ("sonar", "ranging") chain of the sensor model, e.g. for ground-station settings.
 * @return 0, or -1 if the model has no such effect or parameter, or the value is outside the parameter's range
 */
extern int nps_swarm_effect_param(const char *kind, const char *effect, const char *param, double *value, bool set);

/** Ordered pairs of equipped copters within each other's radio horizon now (to foresee the range log's size). */
extern double nps_swarm_ranging_pairs_in_horizon(void);

/* ---- a world shared with other processes (nps_swarm_shared.h) ---- */

/** Whether copter v is in the arena (every copter is, until nps_swarm_set_present takes it out). */
extern bool nps_swarm_present(unsigned v);
/**
 * Put copter v into the arena (at the pose last given to nps_swarm_set_pose) or take it out: an absent copter is
 * seen by no sensor, sends no pulse, is not ranged, does not pull the walls. Only the readings of present copters
 * may be asked for. @return 0, or -1 when out of memory
 */
extern int nps_swarm_set_present(unsigned v, bool present);
/**
 * Every time given to this interface from now on (steps, triggers, readings) is taken plus offset_s: the world's
 * clock, and every logged time, is the caller's clock plus offset_s (0 until set).
 */
extern void nps_swarm_set_clock_offset(double offset_s);
/**
 * Set the walls' plates (angle [rad], rate [rad/s], PID integral [deg s], arena order) as another process stepped
 * them to time_s (caller's clock): until nps_swarm_step_walls, nps_swarm_step neither steps the walls nor logs them.
 * @return 0, or -1 (errno EINVAL) when plates is not the arena's plate count
 */
extern int nps_swarm_follow_walls(const double *angle_rad, const double *rate_rad_s, const double *integral_deg_s,
                                  unsigned plates, double time_s);
/** nps_swarm_step steps and logs the walls again, from their present state (the default). */
extern void nps_swarm_step_walls(void);

/* ---- sonar ring (nps_swarm_sonar.c) ---- */

/**
 * Copter v has a sonar ring that cycles every cycle_s seconds. Real rings are not synchronised: the ring's
 * firing times are shifted by a phase drawn uniformly from [0, cycle_s) from the copter's sonar stream.
 */
extern void nps_swarm_sonar_attach(unsigned v, double cycle_s);
/**
 * Sonar `sonar` (nps_sonar order) of copter v sends a pulse at time_s. Other copters hear it from the next
 * nps_swarm_sonar_publish_pings on (nps_swarm_step calls it first): what a copter hears then does not depend
 * on the order, or the threads, in which the copters of one step run.
 */
extern void nps_swarm_sonar_trigger(unsigned v, unsigned sonar, double time_s);
/** Make the pulses triggered since the last call audible to the other copters. */
extern void nps_swarm_sonar_publish_pings(void);
/**
 * The reading of sonar `sonar` of copter v, triggered at fired_s, at the end of its listening window
 * (now_s): the first surface along its boresight, pulses of other copters' sonars that reach it within the
 * window (cross-talk), and the sonar chain of the sensor model. Logged in the range log.
 * @return the measured range [m], NAN for no reading
 */
extern double nps_swarm_sonar_read(unsigned v, unsigned sonar, double fired_s, double now_s);

/** Ground truth of the last reading of sonar `sonar` of copter v: true range [m], first hit a copter. */
extern void nps_swarm_sonar_last_truth(unsigned v, unsigned sonar, double *true_range_m, bool *target_copter);

/* ---- radio ranging (nps_swarm_ranging.c) ---- */

/** Stop simulating ranging (the host replays recorded ranging instead). */
extern void nps_swarm_ranging_disable(void);
/** Copter v carries a ranging unit (only equipped copters are measured, and measure). */
extern void nps_swarm_ranging_equip(unsigned v);
/** Called for each peer distance measured. */
typedef void (*nps_swarm_ranging_report_fn)(void *ctx, uint16_t peer_id, double distance_m);
/**
 * Copter v measures the distance to every other equipped copter within its radio horizon (twice the
 * ranging chain's maximum range): straight antenna-to-antenna distance (no occlusion of the radio), through
 * the ranging chain of the sensor model; each reading is logged and, unless it is "no reading", reported.
 */
extern void nps_swarm_ranging_measure(unsigned v, double now_s, nps_swarm_ranging_report_fn report, void *ctx);

#endif /* NPS_SWARM_H */
