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
 * @file modules/wall_detector/wall_detector_assignment.h
 * The wall detector's decision sum: the posterior log-odds that a sonar sees a copter, summed exactly over the
 * joint assignments of the sonars to walls and distinct peers (the law is in wall_detector_filter.h).
 */

#ifndef WALL_DETECTOR_ASSIGNMENT_H
#define WALL_DETECTOR_ASSIGNMENT_H

#include "modules/wall_detector/wall_detector_peers.h"

/** Sets of sonars (bit o: sonar o). */
#define WALL_DETECTOR_SONAR_SETS (1 << WALL_DETECTOR_SONAR_NB)

/**
 * The posterior log-odds L that sonar `sonar` sees a copter (wall_detector_filter.h), summed exactly over the
 * assignments.
 * @param weight weight[i][o] = w_ok of the i-th peer in range on sonar o (a wall's weight is 1), finite, >= 0
 * @param peer_nb peers in range, 0..WALL_DETECTOR_MAX_PEERS
 * @return L; -infinity without peers
 */
extern double wall_detector_assignment_log_odds(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb,
    int sonar);

/**
 * The last weights summed and what was found, for every sonar: the weights are the same for the four sonars, and
 * stay the same while the evidence does (e.g. pinned at a bound while every sonar reads walls).
 */
struct wall_detector_assignment_cache {
  bool valid;                                                     ///< the entries below are of `weight`
  unsigned peer_nb;                                               ///< peers summed over
  double weight[WALL_DETECTOR_MAX_PEERS][WALL_DETECTOR_SONAR_NB];  ///< their weights
  double sum[WALL_DETECTOR_SONAR_SETS];                           ///< sums over assignments per set of sonars
  double log_odds[WALL_DETECTOR_SONAR_NB];                        ///< L per sonar, NAN: not computed yet
};

/** wall_detector_assignment_log_odds, from the cache when the weights are the same bits as there (then the same
 * result: one pure function of the same inputs). */
extern double wall_detector_assignment_cached_log_odds(struct wall_detector_assignment_cache *cache,
    const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb, int sonar);

#endif /* WALL_DETECTOR_ASSIGNMENT_H */
