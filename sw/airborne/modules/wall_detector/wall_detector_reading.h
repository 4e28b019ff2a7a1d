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
 * @file modules/wall_detector/wall_detector_reading.h
 * What one sonar reading says about its target, given the ranging distances: the error model of a
 * copter echo, the per-reading log-likelihood ratio the sequence filter accumulates, what a remembered wall
 * predicts, the geometric prior of a peer on a sonar's boresight, and the original single-reading check (the
 * baseline). Pure functions, no state.
 */

#ifndef WALL_DETECTOR_READING_H
#define WALL_DETECTOR_READING_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Horizontal sonars: front, right, back, left (indices 0..3). */
#define WALL_DETECTOR_SONAR_NB 4

/** Class of one sonar reading; the values of the WALL_DETECTION ABI message's class fields. */
enum wall_detector_class {
  WALL_DETECTOR_UNKNOWN = 0,  ///< an echo the evidence does not decide
  WALL_DETECTOR_WALL = 1,     ///< an echo from a wall (or any body without a ranging unit)
  WALL_DETECTOR_COPTER = 2,   ///< an echo from a ranged peer copter
  WALL_DETECTOR_NO_ECHO = 3,  ///< the reading is at or beyond the sonar's maximum range: nothing was hit
};

/** Name of a class in logs: "unknown", "wall", "copter", "none" (any other value: "unknown"). Inline: the loggers
 * of NPS (finken_world) use it without the wall detector's code. */
static inline const char *wall_detector_class_name(uint8_t c)
{
  static const char *const names[] = {
    [WALL_DETECTOR_UNKNOWN] = "unknown", [WALL_DETECTOR_WALL] = "wall", [WALL_DETECTOR_COPTER] = "copter",
    [WALL_DETECTOR_NO_ECHO] = "none",
  };
  return c <= WALL_DETECTOR_NO_ECHO ? names[c] : "unknown";
}

/**
 * The sonar and ranging error models a reading is judged with.
 *
 * Sonar (report section 3): measured = true - (R - offset), R ~ Rayleigh(sonar_sigma_m).
 * Ranging: ranged = centre distance + N(0, ranging_sigma_m^2) (a Gaussian stand-in for the ranging GMM; its
 * bias goes into copter_offset_m). A copter echo's true sonar range is the ranged distance minus
 * copter_offset_m (the target's body radius, this copter's sonar mount offset and the ranging bias).
 * A copter echo reads, with probability crosstalk_prob, as cross-talk from that copter's facing sonar:
 * (path + c dt) / 2 with dt = 0 (report section 3.2's "halving"), i.e. about half the ranged distance, and with
 * probability outlier_prob as anything (multipath, cross-talk from a later trigger).
 * A wall is static: the same sonar reads it again where its remembered readings predict for the copter's present
 * pose, within track_sigma_m (wall_detector_track_ratio).
 */
struct wall_detector_model {
  float sonar_sigma_m;    ///< Rayleigh sigma of the sonar's short readings [m]
  float sonar_offset_m;   ///< offset of the short-reading error, measured = true - (R - offset) [m]
  float ranging_sigma_m;  ///< standard deviation of the ranging error [m], > 0
  float copter_offset_m;  ///< ranged centre distance minus the sonar range of that copter's echo [m]
  float crosstalk_prob;   ///< probability that a copter echo reads as half the ranged distance (cross-talk), 0..1
  float outlier_prob;     ///< probability that a copter echo reads as anything, 0..1 - crosstalk_prob
  float sonar_min_m;      ///< smallest sonar reading [m]
  float sonar_max_m;      ///< largest sonar reading; readings at or above it are no echo [m]
  float ranging_max_m;    ///< ranging maximum; a distance at or above it means "out of range" [m]
  float copter_radius_m;  ///< radius of a copter's body, for the prior of a peer on a boresight [m], > 0
  float track_sigma_m;    ///< sd of a static wall's reading about the range its remembered readings predict [m], > 0
};

/**
 * Density of the shortfall u = (ranged distance - copter offset + sonar offset) - sonar reading of a copter
 * echo: u = R + n, R ~ Rayleigh(sonar_sigma_m), n ~ N(0, ranging_sigma_m^2), i.e. the Rayleigh density
 * convolved with the Gaussian, in closed form (derivation in the .c file).
 * @param u_m shortfall [m]
 * @param sonar_sigma_m Rayleigh sigma [m], > 0
 * @param ranging_sigma_m Gaussian standard deviation [m], > 0
 * @return density [1/m]
 */
extern double wall_detector_shortfall_pdf(double u_m, double sonar_sigma_m, double ranging_sigma_m);

/**
 * Survival function of the shortfall: P(u >= a_m), closed form (derivation in the .c file).
 * @param a_m shortfall [m]
 */
extern double wall_detector_shortfall_sf(double a_m, double sonar_sigma_m, double ranging_sigma_m);

/** Constants of the shortfall distribution for one (s, r) = (sonar sigma, ranging sigma) (the .c file's formulas). */
struct wall_detector_shortfall {
  double s, r;        ///< sonar sigma, ranging sigma [m]
  double v2;          ///< v^2 = s^2 + r^2 [m^2]
  double v3;          ///< v^3 [m^3]
  double rv;          ///< r v [m^2]
  double two_r2;      ///< 2 r^2 [m^2]
  double two_v2;      ///< 2 v^2 [m^2]
  double gauss_coef;  ///< r / (v^2 sqrt(2 pi)) [1/m]
  double s_over_v;    ///< s / v
};

/**
 * What the per-reading functions need of a model, computed once per model (wall_detector_model_terms_init) and
 * again whenever a setting changes it: each constant is computed as the model's formulas compute it, so the
 * results are the same as from the model itself.
 */
struct wall_detector_model_terms {
  struct wall_detector_model model;     ///< the model these are of
  struct wall_detector_shortfall shortfall;  ///< (sonar_sigma_m, ranging_sigma_m)
  double span_m;                        ///< sonar_max_m - sonar_min_m [m]
  double crosstalk_sd_m;                ///< sd of a cross-talk reading, sqrt(r^2 / 4 + s^2) [m]
  double crosstalk_coef;                ///< 1 / (crosstalk_sd_m sqrt(2 pi)) [1/m]
  double echo_prob;                     ///< 1 - outlier_prob - crosstalk_prob
  double clamped_wall_p;                ///< probability that a wall reads at most the minimum
  float track_ratio_max;                ///< span_m / (track_sigma_m sqrt(2 pi)), the remembered wall's ratio at
                                        ///< its prediction (wall_detector_track_ratio)
};

/** Compute the terms of a model. */
extern void wall_detector_model_terms_init(struct wall_detector_model_terms *terms,
    const struct wall_detector_model *model);

/**
 * Log-likelihood ratio of one echo: log p(range | echo from the peer at peer_distance_m) - log p(range | wall).
 * H_copter: the shortfall model, mixed with the cross-talk reading (probability crosstalk_prob) and with a
 * reading unrelated to the peer (probability outlier_prob); H_wall: the echo is unrelated to the peer, from a
 * surface at a uniform range in [sonar_min_m, sonar_max_m]. A reading at the minimum (clamped) is judged by
 * the probabilities of reading at most the minimum (wall_detector_reading_clamped: the same llr for every such
 * reading). Bounded below by log(outlier_prob).
 * @param range_m sonar reading [m], below sonar_max_m
 * @param peer_distance_m ranged distance of the peer [m], below ranging_max_m
 */
extern float wall_detector_reading_llr(const struct wall_detector_model_terms *terms, float range_m,
                                       float peer_distance_m);

/**
 * The echo part of the ratio inside wall_detector_reading_llr for a reading above the minimum, a function of the
 * shortfall alone: (1 - outlier_prob - crosstalk_prob) x shortfall density x span.
 * @param shortfall_m ranged distance - copter_offset_m + sonar_offset_m - reading [m]
 */
extern double wall_detector_echo_part(const struct wall_detector_model_terms *terms, double shortfall_m);

/**
 * The cross-talk part of that ratio, a function of the reading's offset from the cross-talk alone:
 * crosstalk_prob x N(offset; 0, crosstalk_sd_m^2) x span.
 * @param crosstalk_offset_m reading - half the ranged distance [m]
 */
extern double wall_detector_crosstalk_part(const struct wall_detector_model_terms *terms, double crosstalk_offset_m);

/** True for a reading at (clamped to) the sonar's minimum: its llr does not depend on the reading. */
static inline bool wall_detector_reading_clamped(const struct wall_detector_model *model, float range_m)
{
  return !(range_m > model->sonar_min_m);
}

/** The parts of a copter echo's model (wall_detector_reading_llr). */
enum wall_detector_part {
  WALL_DETECTOR_PART_ECHO = 0,       ///< the copter's echo, short by the Rayleigh error
  WALL_DETECTOR_PART_CROSSTALK = 1,  ///< cross-talk from the copter's facing sonar, about half its distance
  WALL_DETECTOR_PART_OUTLIER = 2,    ///< anything
  WALL_DETECTOR_PART_NB = 3
};

/**
 * Which part of the copter echo's model (echo, cross-talk, outlier) explains the reading best, for a peer at
 * peer_distance_m: the largest of the three terms of wall_detector_reading_llr.
 */
extern enum wall_detector_part wall_detector_reading_part(const struct wall_detector_model_terms *terms,
    float range_m, float peer_distance_m);

/**
 * Likelihood ratio of one reading between "a wall, which is the wall this sonar read before with probability keep"
 * and "a wall at an unknown range" (its log is g_sonar, wall_detector_filter.h):
 *   (keep N(range; predicted, track_sigma^2) + (1 - keep) / span) / (1 / span),  span = max - min,
 * i.e. the wall hypothesis's density relative to the uniform one of wall_detector_reading_llr. A reading clamped
 * to the minimum is judged by the probability of reading at most the minimum, as there. At least 1 - keep.
 * @param range_m sonar reading [m], below sonar_max_m
 * @param predicted_m where the remembered wall should read now [m]
 * @param keep probability that the echo comes from the remembered wall if it comes from a wall, 0..1
 */
extern float wall_detector_track_ratio(const struct wall_detector_model_terms *terms, float range_m,
                                       float predicted_m, float keep);

/**
 * Prior probability that a peer at centre distance distance_m lies on a given boresight: the fraction of
 * bearings at which the ray hits its body, asin(copter_radius / d) / pi, with d at least two radii (bodies do not
 * overlap, so the ranged distance is raised to contact).
 */
extern float wall_detector_peer_prior(const struct wall_detector_model *model, float distance_m);

/**
 * The original single-reading check (finken_util_with_Virtual_Ranging_Wall_Check.lua, isFinken): an echo
 * is a copter if some in-range ranging distance lies within eps_m of it, else a wall.
 * @param peer_distances_m ranged distances of the peers [m]; those at or above ranging_max_m are ignored
 * @param eps_m tolerance [m] (the original: 0.286319104)
 * @return WALL_DETECTOR_COPTER, WALL_DETECTOR_WALL, or WALL_DETECTOR_NO_ECHO for range_m >= sonar_max_m
 */
extern enum wall_detector_class wall_detector_baseline_class(const struct wall_detector_model *model, float range_m,
    const float *peer_distances_m, unsigned peer_nb, float eps_m);

/** True when a reading is an echo, i.e. below the sonar's maximum range. */
static inline bool wall_detector_is_echo(const struct wall_detector_model *model, float range_m)
{
  return range_m < model->sonar_max_m;
}

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_READING_H */
