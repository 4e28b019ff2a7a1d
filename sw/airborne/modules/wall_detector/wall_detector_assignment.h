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

#ifdef __cplusplus
extern "C" {
#endif

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
 * The sums over assignments per set of sonars (bit o: sonar o) of the peers' weights, the whole work of
 * wall_detector_assignment_log_odds: the L of every sonar follows from them (wall_detector_assignment_sonar_log_odds).
 * @param weight as for wall_detector_assignment_log_odds
 */
extern void wall_detector_assignment_sums(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb,
    double sum[WALL_DETECTOR_SONAR_SETS]);

/** L of sonar `sonar` from the sums of wall_detector_assignment_sums (the same value as
 * wall_detector_assignment_log_odds of their weights). */
extern double wall_detector_assignment_sonar_log_odds(const double sum[WALL_DETECTOR_SONAR_SETS], int sonar);

/**
 * The posterior odds exp(L) = copter / wall of sonar `sonar` (the sums over the sets with and without the sonar)
 * and the posterior of the likelier class, 1 / (1 + exp(-|L|)), from the sums of wall_detector_assignment_sums.
 * exp(-|L|) = min / max of the two, so the posterior is max / (copter + wall): no exp; and the odds need no log
 * (L = log(odds), exactly wall_detector_assignment_sonar_log_odds).
 */
extern void wall_detector_assignment_sonar_decision(const double sum[WALL_DETECTOR_SONAR_SETS], int sonar,
    double *odds, double *confidence);

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_ASSIGNMENT_H */
