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
 * @file nps_raycast.h
 * Ray casts in the arena against the deflected curtain plates, the copter bodies (vertical cylinders)
 * and the floor (z = 0), and the context values of the range log built on them (ctx_target_copter,
 * ctx_facing_sonars, ctx_blocked, ctx_wall_dist; see /work/shared/spec/range-log.md).
 *
 * A wall column (one segment) has three surfaces: the hinged plate (z from its bottom edge up to the
 * hinge), the fixed curtain above the hinge (up to wallHeight), and the outer sheet at rest behind the
 * plate, which stops a ray slipping through the gap between two differently deflected plates.
 * The sonar geometry ignores roll and pitch (hover): headings are yaw plus the body heading.
 */

#ifndef NPS_RAYCAST_H
#define NPS_RAYCAST_H

#include "nps_arena.h"

/** No copter to skip (copter ids are >= 0). */
#define NPS_RAYCAST_NO_ID (-1)

/** What a ray hit first. */
enum nps_hit_kind {
  NPS_HIT_NOTHING = 0,
  NPS_HIT_WALL,
  NPS_HIT_COPTER,
  NPS_HIT_FLOOR,
  NPS_HIT_OBSTACLE
};

/** Result of a ray cast. */
struct nps_ray_hit {
  enum nps_hit_kind kind;
  double range_m;          /**< distance from the origin to the hit [m]; INFINITY for NPS_HIT_NOTHING */
  double point_m[3];       /**< hit point [m] */
  double normal[3];        /**< unit surface normal at the hit, facing the side the ray came from */
  int wall;                /**< wall index (NPS_HIT_WALL), else -1 */
  int segment;             /**< segment index within the wall (NPS_HIT_WALL), else -1 */
  int plate;               /**< 1: the hinged plate; 0: the fixed curtain above the hinge or the sheet behind */
  int copter_id;           /**< id of the copter hit (NPS_HIT_COPTER), else -1 */
  int obstacle;            /**< index in nps_arena.obstacles (NPS_HIT_OBSTACLE), else -1 */
};

/** The five FINken sonars; body headings front 0, right -90, back 180, left +90 deg; down points to -z. */
enum nps_sonar {
  NPS_SONAR_FRONT = 0,
  NPS_SONAR_RIGHT,
  NPS_SONAR_BACK,
  NPS_SONAR_LEFT,
  NPS_SONAR_DOWN,
  NPS_SONAR_COUNT
};

/** Range-log sensor name of a sonar ("sonar_front", ...). */
const char *nps_sonar_name(enum nps_sonar sonar);

/**
 * First surface along origin + t dir, 0 <= t <= max_range_m. dir need not be unit (it is normalised;
 * a zero dir gives NPS_HIT_NOTHING). The copters with ids skip_a and skip_b are ignored (the emitter; for
 * a line between two copters both ends); NPS_RAYCAST_NO_ID skips none.
 * @return hit->kind
 */
enum nps_hit_kind nps_raycast(const struct nps_arena *a, const double origin_m[3], const double dir[3],
                              double max_range_m, int skip_a, int skip_b, struct nps_ray_hit *hit);

/**
 * nps_raycast without the hit's point and normal (left zero): the kind, range and ids only, what a range
 * reading needs.
 * @return hit->kind
 */
enum nps_hit_kind nps_raycast_range(const struct nps_arena *a, const double origin_m[3], const double dir[3],
                                    double max_range_m, int skip_a, int skip_b, struct nps_ray_hit *hit);

/**
 * Position [m] and unit boresight of a copter's sonar (offset along the boresight from the centre). A horizontal
 * boresight is (cos yaw, sin yaw) (nps_arena_copter_yaw_trig) turned by the sonar's quarter turn: exactly
 * (cos, sin)(yaw + heading) but for the rounding of the sum.
 */
static inline void nps_raycast_sonar_pose(const struct nps_arena *a, const struct nps_arena_copter *c,
                                          enum nps_sonar sonar, double origin_m[3], double dir[3])
{
  /* the headings of the horizontal sonars (FINken layout: front 0, right -90, back 180, left +90 deg) as the rows
   * of the rotations by them: (cos, sin)(yaw + heading) is (cos yaw, sin yaw) turned exactly (a swap and sign
   * changes); inline: every sonar reading starts here */
  static const double turn[4][2][2] = {
    { { 1., 0. }, { 0., 1. } }, { { 0., 1. }, { -1., 0. } }, { { -1., 0. }, { 0., -1. } }, { { 0., -1. }, { 1., 0. } }
  };
  if (sonar == NPS_SONAR_DOWN) {
    dir[0] = 0.;
    dir[1] = 0.;
    dir[2] = -1.;
  } else {
    double cos_yaw, sin_yaw;
    nps_arena_copter_yaw_trig(c, &cos_yaw, &sin_yaw);
    dir[0] = turn[sonar][0][0] * cos_yaw + turn[sonar][0][1] * sin_yaw;
    dir[1] = turn[sonar][1][0] * cos_yaw + turn[sonar][1][1] * sin_yaw;
    dir[2] = 0.;
  }
  /* written out, not a loop (which GCC kept as one): the caller's ray cast then reads the values from registers, not
   * with a 16-byte load of two 8-byte stores just made, which the processor cannot forward (a stall per reading) */
  origin_m[0] = c->pos_m[0] + a->sonar_offset_m * dir[0];
  origin_m[1] = c->pos_m[1] + a->sonar_offset_m * dir[1];
  origin_m[2] = c->pos_m[2] + a->sonar_offset_m * dir[2];
}

/** Ray cast along a copter's sonar boresight, skipping the copter itself. @return hit->kind */
enum nps_hit_kind nps_raycast_sonar(const struct nps_arena *a, const struct nps_arena_copter *c,
                                    enum nps_sonar sonar, double max_range_m, struct nps_ray_hit *hit);

/**
 * ctx_blocked: 1 if a wall or a third copter cuts the straight line p_a -> p_b (the two ranging antennas,
 * of copters id_a and id_b, both skipped); the blocking hit in *hit (may be NULL).
 */
int nps_raycast_line_blocked(const struct nps_arena *a, const double p_a[3], const double p_b[3],
                             int id_a, int id_b, struct nps_ray_hit *hit);

/**
 * ctx_wall_dist: horizontal distance [m] from p to the nearest wall at rest (the polygon), whatever the
 * deflection and the heading. The distance along a sonar's ray to the deflected wall is the range_m of a
 * nps_raycast_sonar hit of kind NPS_HIT_WALL.
 */
double nps_raycast_wall_dist(const struct nps_arena *a, const double p_m[3]);

/** Another copter's sonar that points at a receiving sensor. */
struct nps_facing_sonar {
  int copter_id;           /**< id of the emitting copter */
  enum nps_sonar sonar;    /**< which of its sonars */
  double path_m;           /**< one-way straight path emitter -> receiver [m] */
  double emitter_pos_m[3]; /**< position of the emitting sonar [m] */
  double emitter_dir[3];   /**< its unit boresight */
  double off_axis_rad;     /**< angle of the receiver off the emitter's boresight [rad] */
  double rx_off_axis_rad;  /**< angle of the emitter off the receiver's boresight [rad] */
  int blocked;             /**< 1 if a wall or a third copter cuts the path */
};

/**
 * Other copters' sonars facing sonar rx_sonar of copter rx (ctx_facing_sonars): each lies within the
 * other's beam cone (half_angle_rad) and they are at most range_m apart (nps_crosstalk_facing, the
 * cross-talk model's own test). Line of sight is not required for the count; each listed entry says
 * whether its path is blocked. Candidates come from the copter grid cells within range_m, not from every
 * copter. Up to max_out entries, nearest first, go to out (may be NULL).
 * @return the number of facing sonars, which may exceed max_out
 */
int nps_raycast_facing_sonars(const struct nps_arena *a, const struct nps_arena_copter *rx, enum nps_sonar rx_sonar,
                              double half_angle_rad, double range_m, struct nps_facing_sonar *out, int max_out);

/**
 * The search of nps_raycast_facing_sonars without the details: for a receiving sonar of copter rx_id at
 * p_r with unit boresight b_r (nps_raycast_sonar_pose), the same count and the same nearest-first list,
 * whose entries carry copter_id, sonar, path_m and emitter_pos_m only (emitter_dir and the angles are left
 * NaN, `blocked` -1: a caller that needs the line of sight of a few entries tests them with
 * nps_raycast_line_blocked(a, emitter_pos_m, p_r, copter_id, rx_id, NULL)). Leaving the boresights out
 * spares the exact cone test of most emitters (nps_raycast_sonar.c).
 * @param cos_half_angle  cos of the beam half-angle (0 < half-angle < 90 deg for the tight search box)
 */
int nps_raycast_facing_nearest(const struct nps_arena *a, int rx_id, const double p_r[3], const double b_r[3],
                               double cos_half_angle, double range_m, struct nps_facing_sonar *out, int max_out);

#endif /* NPS_RAYCAST_H */
