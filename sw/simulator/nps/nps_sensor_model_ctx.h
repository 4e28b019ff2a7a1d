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
 * @file nps_sensor_model_ctx.h
 * What a sensor-model chain needs besides the true range: the context of a reading (a small fixed struct,
 * the `ctx_` columns of a range log) and the per-stream state (recent true ranges, for latency).
 */

#ifndef NPS_SENSOR_MODEL_CTX_H
#define NPS_SENSOR_MODEL_CTX_H

#include <stdbool.h>
#include <stddef.h>

struct nps_sensor_chain;

/** Further `ctx_` columns a model may name in conditions, beyond the fixed ones. */
#define NPS_CTX_EXTRA_MAX 8
/** Longest context name, "ctx_" prefix and terminating NUL included. */
#define NPS_CTX_NAME_LEN 48
/** True ranges a stream remembers for latency (at 20 Hz: 6.4 s). */
#define NPS_SENSOR_HISTORY_LEN 128

/** Slots of the context, in struct order; a condition names them by their range-log column names. */
enum nps_ctx_slot {
  NPS_CTX_FACING_SONARS,   /**< "ctx_facing_sonars" */
  NPS_CTX_TARGET_COPTER,   /**< "ctx_target_copter" */
  NPS_CTX_BLOCKED,         /**< "ctx_blocked" */
  NPS_CTX_WALL_DIST,       /**< "ctx_wall_dist" */
  NPS_CTX_SPEED,           /**< "ctx_speed" */
  NPS_CTX_CROSSTALK_PATH,  /**< "ctx_crosstalk_path" */
  NPS_CTX_TRIGGER_OFFSET,  /**< "ctx_trigger_offset" */
  NPS_CTX_FLOOR,           /**< "ctx_floor" */
  NPS_CTX_TARGET_OBSTACLE, /**< "ctx_target_obstacle" */
  NPS_CTX_VEHICLE,         /**< "ctx_vehicle" (a range log's `vehicle` column, not one of its ctx_ columns) */
  NPS_CTX_EXTRA0,          /**< first model-defined column (nps_sensor_model_ctx_slot_name) */
  NPS_CTX_SLOTS = NPS_CTX_EXTRA0 + NPS_CTX_EXTRA_MAX
};

/** Context of one reading; zero-initialise it and fill what the host knows. */
struct nps_sensor_ctx {
  double facing_sonars;     /**< other copters' sonars heard directly (each in the other's cone and range) [count] */
  double target_copter;     /**< 1 when the sonar's first hit is a copter, not a wall or an obstacle */
  double blocked;           /**< 1 when a body cuts the line between two ranging antennas */
  double wall_dist_m;       /**< distance to the nearest wall [m] */
  double speed_mps;         /**< the copter's speed [m/s] */
  double crosstalk_path_m;  /**< one-way path length from the facing emitter [m]; 0 or NaN: the true range */
  double trigger_offset_s;  /**< emitter's trigger time minus this sensor's trigger time [s] */
  double floor;             /**< downward sonar: code of the floor material under the copter (nps_floor.h); else 0 */
  double target_obstacle;   /**< 1 when the sonar's first hit is an interior obstacle (nps_obstacle.h) */
  double vehicle;           /**< aircraft id of the copter carrying the sensor (per-vehicle: ctx_vehicle == 2) */
  double extra[NPS_CTX_EXTRA_MAX]; /**< model-defined columns, slot NPS_CTX_EXTRA0 + i */
};

/** Recent (time, true range) pairs of one sensor stream; a ring buffer. */
struct nps_sensor_state {
  double t_s[NPS_SENSOR_HISTORY_LEN];
  double true_range_m[NPS_SENSOR_HISTORY_LEN];
  unsigned newest;   /**< index of the newest entry */
  unsigned count;    /**< entries filled (<= NPS_SENSOR_HISTORY_LEN) */
};

/** NPS_CTX_SLOTS, for bindings. */
int nps_sensor_ctx_slot_count(void);
/** The value of a slot (0 for NULL ctx or an out-of-range slot). */
double nps_sensor_ctx_get(const struct nps_sensor_ctx *ctx, int slot);
/** Set a slot's value (ignored for an out-of-range slot). */
void nps_sensor_ctx_set(struct nps_sensor_ctx *ctx, int slot, double value);
/** The column name of a fixed slot ("ctx_blocked", ...), NULL for extra slots. */
const char *nps_sensor_ctx_fixed_name(int slot);
/**
 * True when applying the chain (nps_sensor_chain_apply) may read context slot `slot`: a term of an effect's
 * condition names it, or the effect itself reads it (crosstalk: facing sonars, crosstalk path, trigger offset; a
 * bias_curve: its `over` column). A host need not compute a value that neither the chain nor its log reads. False
 * for a NULL chain.
 */
bool nps_sensor_chain_reads_ctx(const struct nps_sensor_chain *chain, int slot);

void nps_sensor_state_init(struct nps_sensor_state *state);
/** Remember the true range at time t_s (times of one stream must not decrease). */
void nps_sensor_state_push(struct nps_sensor_state *state, double t_s, double true_range_m);
/**
 * The true range at time t_s, linearly interpolated between the remembered readings; the oldest remembered
 * value when t_s is older than all of them; NaN when nothing is remembered.
 */
double nps_sensor_state_true_range_at(const struct nps_sensor_state *state, double t_s);

#endif /* NPS_SENSOR_MODEL_CTX_H */
