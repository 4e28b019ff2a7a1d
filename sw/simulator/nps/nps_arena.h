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
 * @file nps_arena.h
 * The arena: a closed polygon of curtain walls, each split into hinged plates (segments), and the
 * copters flying in it. Frame: ENU arena frame, x east, y north, z up [m]; yaw [rad] from x toward y.
 *
 * Life cycle: build from an XML file (nps_arena_load) or from code (nps_arena_new_rectangle, or fill a
 * struct nps_arena_config and call nps_arena_build); every simulation step give the copters
 * (nps_arena_set_copters) and advance the walls (nps_arena_walls_step in nps_walls.h); cast rays
 * (nps_raycast.h); nps_arena_free at the end. Structures are public for reading; change them only
 * through these functions.
 */

#ifndef NPS_ARENA_H
#define NPS_ARENA_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "nps_floor.h"
#include "nps_obstacle.h"

/** Length of the source name kept for error messages. */
#define NPS_ARENA_SOURCE_LEN 256
/** Length of the arena name. */
#define NPS_ARENA_NAME_LEN 64

/**
 * Parameters of the curtain plates of one wall. XML attribute names (the report's, section 2.4.2, plus
 * ours) in brackets; units are ours, justified in docs/arena-and-walls.md.
 */
struct nps_wall_params {
  int num_segments;              /**< [numSegments] plates per wall */
  double wall_width_m;           /**< [wallWidth] expected wall length [m], checked against the polygon; 0 = not given */
  double segment_mass_kg;        /**< [segmentMass] plate mass, sets the hinge inertia m L^2 / 3 [kg] */
  double joint_force_nm;         /**< [jointForce] saturation of the motor (PID) torque [N m] */
  double threshold_m;            /**< [threshold] copter distance below which the PID drives the plate [m] */
  double friction_nm;            /**< [friction] Coulomb friction torque of a free hinge [N m] */
  double max_amplitude_deg;      /**< [maxAmplitude] k of the amplitude law, hinge angle [deg] */
  double pid_p;                  /**< [PID_P] proportional gain [N m / deg] */
  double pid_i;                  /**< [PID_I] integral gain [N m / (deg s)] */
  double pid_d;                  /**< [PID_D] derivative gain [N m s / deg] */
  double hinge_height_m;         /**< [hingeHeight] height of the hinge (top edge) = plate length L [m] */
  double curtain_mass_kg;        /**< [curtainMass] weight pulling the plate back to vertical [kg] */
  double friction_velocity_rad_s;/**< [frictionVelocity] speed below which Coulomb friction fades (tanh) [rad/s] */
  int line;                      /**< line of the XML element these came from (0: from code) */
};

/** A polygon corner as given in the configuration. */
struct nps_arena_point {
  double x_m, y_m;               /**< position, arena frame [m] */
  int line;                      /**< XML line (0: from code) */
};

/** Everything an arena is built from; filled by the XML loader or by code. */
struct nps_arena_config {
  char source[NPS_ARENA_SOURCE_LEN]; /**< file name (or a description) for error messages */
  char name[NPS_ARENA_NAME_LEN];     /**< arena name */
  int line;                          /**< line of <arena> */
  struct nps_arena_point *points;    /**< polygon corners; closed: the last repeats the first */
  int num_points;                    /**< number of points including the closing one */
  int polygon_line;                  /**< line of <polygon> */
  struct nps_wall_params *walls;     /**< per wall (edge i: points[i] -> points[i+1]), num_points - 1 entries */
  double flight_height_m;            /**< [flightHeight] nominal flight height [m] */
  double wall_height_m;              /**< [wallHeight] height of the curtain walls [m] */
  double copter_radius_m;            /**< [copters radius] default body radius [m] */
  double copter_height_m;            /**< [copters height] default body height (vertical cylinder) [m] */
  int copters_line;                  /**< line of <copters> */
  double sonar_half_angle_deg;       /**< [sonars beamHalfAngle] default beam half-angle [deg] */
  double sonar_range_m;              /**< [sonars range] default maximum range [m] */
  double sonar_offset_m;             /**< [sonars offset] sonar position from the copter centre along its boresight [m] */
  int sonars_line;                   /**< line of <sonars> */
  struct nps_floor floor;            /**< [floor] materials under the downward sonar (nps_floor.h) */
  struct nps_obstacle *obstacles;    /**< [obstacle] interior obstacles (nps_obstacle.h), in file order */
  int num_obstacles;
};

/** One curtain wall: an edge of the polygon. */
struct nps_wall {
  double a[2], b[2];             /**< rest endpoints on the floor [m], a -> b along the polygon */
  double t[2];                   /**< unit direction a -> b */
  double n[2];                   /**< unit horizontal normal pointing into the arena */
  double length_m;               /**< |b - a| [m] */
  double plates_per_m;           /**< p.num_segments / length_m: plate k spans [k, k + 1] / plates_per_m along
                                      it [1/m] */
  struct nps_wall_params p;      /**< parameters */
  double inertia_kgm2;           /**< hinge inertia m L^2 / 3 (thin plate about its edge) [kg m^2] */
  double restore_nm;             /**< gravity torque scale curtainMass g L / 2: torque = -restore sin(angle) [N m] */
  double substep_s;              /**< largest stable integration step for these parameters [s] */
  int first_segment;             /**< index of its first segment in nps_arena.segs */
};

/** One hinged plate: geometry at rest and dynamic state. */
struct nps_wall_segment {
  double a[2], b[2];             /**< rest endpoints on the floor [m] */
  double length_m;               /**< |b - a| [m] */
  int wall;                      /**< index of its wall */
  int index;                     /**< index within its wall */
  double angle_rad;              /**< hinge angle: 0 hanging at rest, > 0 bottom edge toward the arena [rad] */
  double rate_rad_s;             /**< hinge angular rate [rad/s] */
  double integral_deg_s;         /**< PID integral of the angle error [deg s] */
  double target_deg;             /**< current PID target (0 when free) [deg] */
  double limit_rad;              /**< largest angle this step: contact with the driving copter's body when the
                                      plate can reach it within the step, else pi/2 [rad] */
  double nearest_m;              /**< horizontal distance to the nearest copter this step (INFINITY if none within threshold) [m] */
  int nearest_copter;            /**< index in nps_arena.copters of that copter, -1 if none */
  int driven;                    /**< 1 while a copter within threshold drives the PID */
  int active;                    /**< 1 while listed in nps_arena.active_segs */
};

/** A copter as the host gives it every step. */
struct nps_arena_copter {
  int id;                        /**< vehicle id (>= 0) */
  int yaw_trig_valid;            /**< 1: the memo below is current for trig_yaw_rad and base_yaw_rad (0 in a copter
                                      built by hand) */
  double pos_m[3];               /**< centre, arena frame ENU [m] */
  double yaw_rad;                /**< heading from x toward y [rad] */
  double radius_m;               /**< body radius (vertical cylinder) [m] */
  double height_m;               /**< body height [m] */
  /* memo of cos and sin of the yaw, for the sonar boresights (turned from it by quarter turns): kept by
   * nps_arena_copter_make and, for the arena's copters, nps_arena_set_copters and nps_arena_poses_moved;
   * read through nps_arena_copter_yaw_trig, which never uses a stale one */
  double cos_yaw, sin_yaw;       /**< cos(trig_yaw_rad), sin(trig_yaw_rad) [-] (nps_arena_copter_recompute_yaw_trig) */
  double trig_yaw_rad;           /**< the yaw they are of [rad] */
  double base_yaw_rad;           /**< the last yaw whose cos and sin came from libm (valid with yaw_trig_valid) [rad] */
  double cos_base, sin_base;     /**< cos(base_yaw_rad), sin(base_yaw_rad) from libm [-] */
};

/**
 * Largest turn [rad] from the base yaw for which the memo is the base turned by the angle-addition formula
 * instead of computed by libm: 2^-16. The yaw of a copter that holds its heading creeps by ~1e-9 rad per step
 * after its float heading command, so most steps need no libm call.
 */
#define NPS_ARENA_YAW_TRIG_TURN_MAX_RAD 0x1p-16

/**
 * Make c's memo of cos and sin of its yaw current, its yaw having changed since (nps_arena_copter_refresh_yaw_trig
 * calls it only then). Within NPS_ARENA_YAW_TRIG_TURN_MAX_RAD of the base yaw b the memo is
 * (cos, sin)(b + d) = (cos b cos d - sin b sin d, sin b cos d + cos b sin d), d = yaw - b, with cos d = 1 - d^2/2
 * and sin d = d - d^3/6 (the omitted terms, d^4/24 <= 2^-64/24 and d^5/120, are below 1e-20); so it differs from
 * libm's cos and sin of the yaw by the rounding of a few operations, at most 2^-52 (tested), like the rounding of the
 * yaw itself (2^-51 near pi).
 * Farther, or on a copter whose memo is not valid, libm gives a new base.
 */
void nps_arena_copter_recompute_yaw_trig(struct nps_arena_copter *c);

/** Whether c's memo of cos and sin is of its current yaw. */
static inline int nps_arena_copter_yaw_trig_current(const struct nps_arena_copter *c)
{
  return c->yaw_trig_valid && c->trig_yaw_rad == c->yaw_rad;
}

/** Make c's memo of cos and sin of its yaw current: a comparison when the yaw did not change (nearly every step). */
static inline void nps_arena_copter_refresh_yaw_trig(struct nps_arena_copter *c)
{
  if (!nps_arena_copter_yaw_trig_current(c)) {
    nps_arena_copter_recompute_yaw_trig(c);
  }
}

/**
 * cos and sin of c's yaw: its memo when that is of its current yaw, else computed by libm (the memo is within 2^-52
 * of libm's values, see nps_arena_copter_recompute_yaw_trig).
 */
static inline void nps_arena_copter_yaw_trig(const struct nps_arena_copter *c, double *cos_yaw, double *sin_yaw)
{
  if (nps_arena_copter_yaw_trig_current(c)) {
    *cos_yaw = c->cos_yaw;
    *sin_yaw = c->sin_yaw;
  } else {
    *cos_yaw = cos(c->yaw_rad);
    *sin_yaw = sin(c->yaw_rad);
  }
}

struct nps_arena_grid;

/** The arena (see the file comment). */
struct nps_arena {
  char name[NPS_ARENA_NAME_LEN];
  int num_walls;
  struct nps_wall *walls;
  int num_segments;              /**< total over all walls */
  struct nps_wall_segment *segs;
  double flight_height_m;        /**< nominal flight height [m] */
  double wall_height_m;          /**< curtain height [m] */
  double copter_radius_m;        /**< default copter body radius [m] */
  double copter_height_m;        /**< default copter body height [m] */
  double sonar_half_angle_rad;   /**< default sonar beam half-angle [rad] */
  double sonar_cos_half_angle;   /**< its cosine [-] (the facing search tests cones by cosines) */
  double sonar_range_m;          /**< default sonar range [m] */
  double sonar_offset_m;         /**< sonar position from the copter centre along its boresight [m] */
  struct nps_floor floor;        /**< floor materials (nps_floor_material_at gives ctx_floor) */
  struct nps_obstacle *obstacles;/**< interior obstacles, finished (nps_obstacle_finish): counter-clockwise, boxed */
  int num_obstacles;
  int num_copters;
  int copters_capacity;
  struct nps_arena_copter *copters;
  struct nps_arena_grid *grid;   /**< spatial index of segments and copters */
  int *active_segs;              /**< the plates a wall step integrates: driven or not at rest (any order);
                                      every other plate is free and at rest, with target 0, limit pi/2, no nearest copter */
  int num_active;
  double time_s;                 /**< time of the last wall step [s] */
  int stepped;                   /**< 0 until the first wall step */
};

/** The report's recommended values (section 2.4.2) and our defaults for the added parameters. */
void nps_wall_params_default(struct nps_wall_params *p);

/** An empty configuration with defaults (SwarmLab heights, copter and sonar defaults) and no polygon. */
void nps_arena_config_init(struct nps_arena_config *cfg, const char *source);

/** Release what a configuration owns (points, walls, floor, obstacles); the struct may be reused after init. */
void nps_arena_config_free(struct nps_arena_config *cfg);

/**
 * Set the polygon of cfg to the rectangle [0, width] x [0, depth] (counter-clockwise) with default wall
 * parameters and segments_per_wall plates per wall.
 * @return 0, or -1 with a message in err
 */
int nps_arena_config_rectangle(struct nps_arena_config *cfg, double width_m, double depth_m,
                               int segments_per_wall, char *err, size_t err_len);

/**
 * Scale the polygon (and the given wallWidth values) and the obstacles' footprints by factor about the origin;
 * heights, thresholds and copter sizes keep their values (a larger arena for more copters at the same density).
 * @return 0, or -1 with a message in err
 */
int nps_arena_config_scale(struct nps_arena_config *cfg, double factor, char *err, size_t err_len);

/** Read an arena XML file into cfg (initialised by this call). @return 0, or -1 with "file:line: reason" in err */
int nps_arena_config_load(struct nps_arena_config *cfg, const char *path, char *err, size_t err_len);

/** Check a configuration: each failure gives "source:line: reason". @return 0 or -1 */
int nps_arena_config_check(const struct nps_arena_config *cfg, char *err, size_t err_len);

/**
 * Whether a copter copter_height_m tall flying at height z_m fits between the floor (z = 0) and the wall top at
 * wall_height_m: its body clear of the floor, not above the curtains (false for a NaN). The arena check asks it
 * of flightHeight, the host of its flight model's altitude.
 */
bool nps_arena_height_fits(double copter_height_m, double wall_height_m, double z_m);

/** Build an arena from a checked-or-not configuration (it is checked). @return the arena or NULL with err */
struct nps_arena *nps_arena_build(const struct nps_arena_config *cfg, char *err, size_t err_len);

/** Load and build; never returns a half-loaded arena. @return the arena or NULL with "file:line: reason" */
struct nps_arena *nps_arena_load(const char *path, char *err, size_t err_len);

/** A rectangle width x depth [m] with segments_per_wall plates per wall and default parameters. */
struct nps_arena *nps_arena_new_rectangle(double width_m, double depth_m, int segments_per_wall,
                                          char *err, size_t err_len);

/** Free an arena (NULL is fine). */
void nps_arena_free(struct nps_arena *a);

/** A copter with the arena's default body size at the given pose. */
struct nps_arena_copter nps_arena_copter_make(const struct nps_arena *a, int id, double x_m, double y_m,
                                              double z_m, double yaw_rad);

/**
 * Give the copters of this step (copied) and rebuild the copter index. Ids must be >= 0 and unique (uniqueness is not checked).
 * @return 0, or -1 with errno EINVAL (negative id, non-finite pose, non-positive size) or ENOMEM
 */
int nps_arena_set_copters(struct nps_arena *a, const struct nps_arena_copter *copters, int n);

/**
 * The poses (pos_m, yaw_rad) of a->copters were changed in place (written straight into the arena, as nps_swarm
 * does to spare a copy of every copter each step): check the poses and rebuild the copter index. Ids and sizes
 * must be those checked by nps_arena_set_copters (to change them, give the copters again).
 * @return 0, or -1 with errno EINVAL (a pose not finite; the index is then stale) or ENOMEM
 */
int nps_arena_poses_moved(struct nps_arena *a);

/**
 * Obstacle i's footprint as at most max_points corners (x, y) in xy [m] (nps_obstacle_outline) and its height.
 * @return the footprint's number of corners, or -1 when there is no obstacle i (for bindings: Python draws the
 * obstacles)
 */
int nps_arena_obstacle_outline(const struct nps_arena *a, int i, double *xy, int max_points, double *height_m);

/** Whether obstacle i is a circle (1, its centre x, y and radius in circle [m]), a polygon (0) or absent (-1). */
int nps_arena_obstacle_circle(const struct nps_arena *a, int i, double circle[3]);

/** Index of the copter with this id in a->copters, or -1. */
int nps_arena_copter_index(const struct nps_arena *a, int id);

/** Called for each copter found by nps_arena_copters_near. */
typedef void (*nps_arena_copter_visit_fn)(void *ctx, const struct nps_arena_copter *c);
/**
 * Visit every copter whose centre lies in the square of half-side reach_m around (x_m, y_m) (callers
 * apply their own exact distance test), through the copter grid: cost grows with the copters nearby,
 * not with all the copters.
 */
void nps_arena_copters_near(const struct nps_arena *a, double x_m, double y_m, double reach_m,
                            nps_arena_copter_visit_fn visit, void *ctx);

#endif /* NPS_ARENA_H */
