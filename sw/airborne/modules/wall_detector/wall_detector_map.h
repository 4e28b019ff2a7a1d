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
 * @file modules/wall_detector/wall_detector_map.h
 * The wall map: where the walls are, remembered for the whole flight (the detector's law when WALL_DETECTOR_MAP
 * is TRUE; docs/wall-detector.md).
 *
 * Lines. A wall stays where it is and is a straight line. The map keeps up to WALL_DETECTOR_MAP_LINES lines in the
 * frame of the copter's position estimate, each learned from the echoes of all four sonars: an echo read r along
 * the unit boresight u from the copter at x comes from q = x + r u. A line is
 *   { q : n . (q - c) = d },   n = (sin theta, cos theta) (east, north),
 * with theta the bearing of its normal (pointing away from the copters that see it), c a point on it (d = 0 after
 * each echo) and an extent [s_min, s_max] along t = dn/dtheta = (n_y, -n_x) from c where its echoes came from.
 * A beam meets it at
 *   r = (d - n . (x - c)) / (n . u)       (echo place s = t . (x + r u - c)),
 * when n . u >= WALL_DETECTOR_MAP_COS_INCIDENCE (steeper echoes do not come back) and s lies within the extent
 * widened by WALL_DETECTOR_MAP_REACH. The nearest line met is the wall the map predicts: r0.
 *
 * Learning. Each line is an extended Kalman filter of (d, theta) (Bar-Shalom, Li, Kirubarajan, "Estimation with
 * Applications to Tracking and Navigation", 2001, sections 5.2 and 10.3): the reading is r + noise of sd
 * track_sigma_m, with Jacobian dr/d(d, theta) = (1, -s) / (n . u); before the update c moves to the echo's place
 * (the covariance carried along, P' = T P T', T = [1 -s; 0 1]) and after it to the updated line, so d and theta stay
 * nearly uncorrelated. A new line starts square to the beam that saw it (theta the beam's bearing, sd angle_sd_rad).
 * Between echoes d diffuses by drift_m2_per_s per second: the position estimate of an INS drifts, and a line must
 * follow where the copter believes the wall is. The map learns from an echo judged a wall, or one no peer explains
 * (wall_detector_map_explains: a body would be ranged). Such an echo fuses into the line that
 * predicts it within WALL_DETECTOR_MAP_GATE sd (one a peer explains only if that sd is below
 * WALL_DETECTOR_MAP_EXPLAINED_SD ranging sds), else starts a line (in a free place, else in that of an unconfirmed
 * line, else of the line fused longest ago), unless it lies in front of a confirmed line (a body between the copter
 * and a wall: sound does not pass a wall to come back from a second one nearer) or in an unconfirmed line's bulge
 * (below). Any echo beyond a line by
 * more than the gate, where the line was seen (its extent widened by a body radius), shows the line was no wall:
 * sound does not pass a wall. The line is forgotten.
 *
 * Walls and bodies. A body that stays still in a beam (a hovering peer) reads like a wall. But a body is one peer,
 * and ranged: its peer explains nearly all its echoes. A line is confirmed once it has WALL_DETECTOR_MAP_CONFIRM
 * echoes seen with a peer in range and no one peer explained more than WALL_DETECTOR_MAP_BODY_SHARE of them; until
 * then it says nothing.
 *
 * What the map says about a reading: g, the log ratio of the wall hypothesis to a wall at an unknown range (uniform
 * over the sonar's span). Curtains bulge toward a copter near them, so a wall echo reads either at the line,
 * N(r0, S) with S the prediction's variance plus track_sigma_m^2, or, with probability bulge_prob, anywhere up to
 * bulge_m in front of it:
 *   g = log( keep span [ (1 - bulge_prob) N(r; r0, S) + bulge_prob U(r; r0 - bulge_m, r0) ] + (1 - keep) ),
 * keep = 1 - outlier_prob for a confirmed line. A reading at the sonar's minimum takes the probabilities of reading
 * at most the minimum instead of the densities.
 *
 * Cost (Cortex-M4, single-precision FPU): memory WALL_DETECTOR_MAP_LINES lines of 48 + 2 WALL_DETECTOR_MAX_PEERS
 * bytes (8 x 80 = 640 bytes at 16 peers); per echo two passes over the lines (about 30 flops and a sqrtf each),
 * one 2 x 2 Kalman update with a sinf and a cosf, one expf, one erfcf at the minimum and one logf.
 */

#ifndef WALL_DETECTOR_MAP_H
#define WALL_DETECTOR_MAP_H

#include "modules/wall_detector/wall_detector_peers.h"
#include "modules/wall_detector/wall_detector_pose.h"
#include "modules/wall_detector/wall_detector_reading.h"

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Lines remembered (a rectangular arena has 4 walls; the other places hold candidates) */
#ifndef WALL_DETECTOR_MAP_LINES
#define WALL_DETECTOR_MAP_LINES 8
#endif

/** An echo this many sd from a line's prediction fuses into it; this far beyond it, it shows the line was no wall
 * (3: 0.13 % of a wall's readings fall farther on one side) */
#ifndef WALL_DETECTOR_MAP_GATE
#define WALL_DETECTOR_MAP_GATE 3.f
#endif

/** How far beyond the extent of its echoes a line predicts and grows [m] */
#ifndef WALL_DETECTOR_MAP_REACH
#define WALL_DETECTOR_MAP_REACH 1.f
#endif

/** Cosine of the steepest incidence from which a wall echo comes back (75 deg) */
#ifndef WALL_DETECTOR_MAP_COS_INCIDENCE
#define WALL_DETECTOR_MAP_COS_INCIDENCE 0.26f
#endif

/** A peer explains an echo when its llr exceeds this: the echo is e times likelier from it than from a wall at an
 * unknown range */
#ifndef WALL_DETECTOR_MAP_EXPLAINS_LLR
#define WALL_DETECTOR_MAP_EXPLAINS_LLR 1.f
#endif

/** An echo a peer explains fuses into a line only while the line predicts it with an sd below this many ranging
 * sds (a line unseen for long, its offset diffused by the drift, would take a body's echo for the wall's) */
#ifndef WALL_DETECTOR_MAP_EXPLAINED_SD
#define WALL_DETECTOR_MAP_EXPLAINED_SD 2.f
#endif

/** Echoes a line needs before it can be confirmed */
#ifndef WALL_DETECTOR_MAP_CONFIRM
#define WALL_DETECTOR_MAP_CONFIRM 4
#endif

/** Largest share of a line's echoes one peer may explain for it to be a wall (a body's peer explains nearly all:
 * all but its outliers, 10 % in the default error model) */
#ifndef WALL_DETECTOR_MAP_BODY_SHARE
#define WALL_DETECTOR_MAP_BODY_SHARE 0.9f
#endif

/** A position estimate that moves farther than WALL_DETECTOR_MAP_JUMP_M plus WALL_DETECTOR_MAP_JUMP_SPEED times the
 * time since a sonar's previous reading has jumped to a new frame (an INS setting its origin at the first GPS fix):
 * the map is forgotten [m, m/s] */
#ifndef WALL_DETECTOR_MAP_JUMP_M
#define WALL_DETECTOR_MAP_JUMP_M 0.5f
#endif
#ifndef WALL_DETECTOR_MAP_JUMP_SPEED
#define WALL_DETECTOR_MAP_JUMP_SPEED 5.f
#endif
/** Likewise a heading that turns farther than WALL_DETECTOR_MAP_JUMP_RAD plus WALL_DETECTOR_MAP_JUMP_YAW_RATE times
 * the time [rad, rad/s] */
#ifndef WALL_DETECTOR_MAP_JUMP_RAD
#define WALL_DETECTOR_MAP_JUMP_RAD 0.2f
#endif
#ifndef WALL_DETECTOR_MAP_JUMP_YAW_RATE
#define WALL_DETECTOR_MAP_JUMP_YAW_RATE 3.f
#endif

/** Parameters of the map (each mirrors a WALL_DETECTOR_* define). */
struct wall_detector_map_params {
  float drift_m2_per_s;  ///< diffusion of the position estimate's error per axis [m^2/s]
  float angle_sd_rad;    ///< prior sd of a new line's angle from square to the beam that saw it [rad]
  float bulge_m;         ///< how far in front of its line a curtain may bulge toward a copter [m], > 0
  float bulge_prob;      ///< probability that a wall echo comes from a bulge, 0..1
};

/** One remembered wall (file comment). */
struct wall_detector_map_line {
  bool used;
  float c_x_m, c_y_m;        ///< point c, east and north [m]
  float theta_rad;           ///< bearing of the normal [rad]
  float n_x, n_y;            ///< the normal (sin theta, cos theta)
  float p_dd_m2, p_dt_m, p_tt_rad2;  ///< covariance of (d, theta) at c
  float s_min_m, s_max_m;    ///< extent of its echoes along t from c [m]
  uint32_t stamp_us;         ///< time of the last echo fused (d's variance grows since)
  uint16_t echoes;           ///< echoes fused
  uint16_t explained[WALL_DETECTOR_MAX_PEERS];  ///< of them, those each peer slot explained
};

/** The map of one copter. */
struct wall_detector_map {
  struct wall_detector_map_line line[WALL_DETECTOR_MAP_LINES];
};

/** A reading's beam: where it starts and where it points. */
struct wall_detector_map_beam {
  float x_m, y_m;   ///< the copter, east and north [m]
  float u_x, u_y;   ///< the unit boresight, east and north
};

/** What the map predicts for a beam. */
struct wall_detector_map_prediction {
  bool known;       ///< a confirmed line is met (else the rest is 0)
  float range_m;    ///< r0, where the nearest confirmed line met should read [m]
  float var_m2;     ///< S, the variance of a reading about r0 without bulge [m^2]
};

/** The beam of the sonar at bearing bearing_rad (clockwise from north) from pose. */
extern struct wall_detector_map_beam wall_detector_map_beam_of(const struct wall_detector_pose *pose,
    float bearing_rad);

/** The map's prediction for a beam at now_us: the nearest line met, if it is confirmed. */
extern struct wall_detector_map_prediction wall_detector_map_predict(const struct wall_detector_map *map,
    const struct wall_detector_map_params *params, const struct wall_detector_model *model,
    const struct wall_detector_map_beam *beam, uint32_t now_us);

/** exp(g) (file comment) of reading range_m against a known prediction: the ratio of the wall hypothesis to a wall
 * at an unknown range (what the filter averages with the sonar's own memory). */
extern float wall_detector_map_ratio(const struct wall_detector_model_terms *terms,
                                     const struct wall_detector_map_params *params,
                                     const struct wall_detector_map_prediction *prediction, float range_m);

/**
 * Learn from an echo (file comment): forget the lines it falls beyond; when it was judged a wall or explained_by is
 * empty, fuse it into a line or start one. An echo closer than two body radii teaches nothing.
 * @param peers_in_range a peer was in range: only then does the echo count toward a line's confirmation (with no
 *        peer ranged, as before the ranging runs, a body's echo is explained by none)
 * @param explained_by the peer slots that explain it as their echo (bit k: slot k; wall_detector_map_explains)
 * @param crosstalk_of the peer slots whose cross-talk it may be, with the sonar's evidence favouring them
 *        (wall_detector_map_crosstalk_of): they count as explaining it in the line's counts, but it still teaches
 */
extern void wall_detector_map_learn(struct wall_detector_map *map, const struct wall_detector_map_params *params,
                                    const struct wall_detector_model *model,
                                    const struct wall_detector_map_beam *beam, float range_m, bool judged_wall,
                                    bool peers_in_range, uint32_t explained_by, uint32_t crosstalk_of,
                                    uint32_t now_us);

/** Whether a peer whose llr for an echo is llr explains it: the echo is e times likelier from it than from a wall
 * at an unknown range (WALL_DETECTOR_MAP_EXPLAINS_LLR). */
static inline bool wall_detector_map_explains(float llr)
{
  return llr > WALL_DETECTOR_MAP_EXPLAINS_LLR;
}

/** Whether an echo read range_m lies within 2 sd of the cross-talk of a peer at peer_distance_m, half its distance
 * (facing copters read that way far more often than the model's crosstalk_prob, an average over all copters). */
static inline bool wall_detector_map_crosstalk_of(const struct wall_detector_model_terms *terms, float range_m,
    float peer_distance_m)
{
  return fabsf(range_m - 0.5f * peer_distance_m) <= 2.f * (float)terms->crosstalk_sd_m;
}

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_MAP_H */
