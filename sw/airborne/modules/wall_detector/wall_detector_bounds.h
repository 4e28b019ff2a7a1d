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
 * @file modules/wall_detector/wall_detector_bounds.h
 * Cheap bounds of expf and logf (a few multiplications, no libm call), for tests that need only to know that a value
 * lies beyond a threshold: the filter decides with them when a reading's discount cannot matter
 * (wall_detector_filter_surely_pinned, with the track llr's bound wall_detector_track_llr_lower_bound) and when a
 * peer's evidence surely ends at a bound whatever its llr's last digits (updated_evidence), and computes the
 * functions themselves otherwise.
 *
 * Each bound is beyond the libm result, not only beyond the exact function: its margin (relative for exp, absolute
 * for log) exceeds its own float rounding plus one unit in the last place of expf and logf (glibc: at most 0.502 and
 * 0.52 ulp, i.e. 6e-8 relative). tests/c/airborne/test_wall_detector_bounds.c checks them against libm on dense
 * grids, near 0 for exp and on every mantissa for log, where the bounds are tightest.
 */

#ifndef WALL_DETECTOR_BOUNDS_H
#define WALL_DETECTOR_BOUNDS_H

#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Squarings in wall_detector_expf_lower_bound: (1 + x / 16)^16 is within about x^2 / 32 relative of exp(x) for
 * |x| <= 1 */
#define WALL_DETECTOR_EXP_BOUND_SQUARINGS 4

/** Relative margin of wall_detector_expf_lower_bound: above the rounding of its float operations, whose relative
 * errors double with each squaring (at most 31 units of 2^-24 = 1.9e-6 all told), and expf's 6e-8 */
#define WALL_DETECTOR_EXP_BOUND_MARGIN 1e-5f

/** Absolute margin of wall_detector_logf_lower_bound [log units]: above its float rounding (the conversion's 2.6e-6
 * and the product's 3.8e-6 for logs up to 89) and logf's 0.52 ulp (below 5e-6 for logs up to 89) */
#define WALL_DETECTOR_LOG_BOUND_MARGIN 2e-5f

/**
 * A lower bound of expf(x) for x <= 0: (1 + x / n)^n with n = 2^WALL_DETECTOR_EXP_BOUND_SQUARINGS, below exp(x)
 * because log(1 + y) <= y (0 where 1 + x / n <= 0), less the margin. For |x| <= 1 within about x^2 / 32 + 1e-5
 * relative of expf(x) (1 % at x = -0.6), looser farther out. NaN gives 0.
 */
static inline float wall_detector_expf_lower_bound(float x)
{
  float power = 1.f + x * (1.f / (float)(1 << WALL_DETECTOR_EXP_BOUND_SQUARINGS));  // x / n is exact
  if (!(power > 0.f)) {
    return 0.f;
  }
  for (int i = 0; i < WALL_DETECTOR_EXP_BOUND_SQUARINGS; i++) {
    power *= power;
  }
  return power * (1.f - WALL_DETECTOR_EXP_BOUND_MARGIN);
}

/** Largest distance of wall_detector_logf_lower_bound below logf [log units]: log(2) times the largest gap between
 * log2(m) and its chord m - 1 on [1, 2) (0.0861 at m = 1 / log(2), i.e. 0.05966), and the margin; the upper bound is
 * the lower one raised by it */
#define WALL_DETECTOR_LOG_BOUND_WIDTH 0.0598f

/**
 * A lower bound of logf(y) for a positive normal y (at least 2^-126; +infinity too), with no division: with
 * y = m 2^e, m in [1, 2), log(y) = log(2) (e + log2(m)) >= log(2) (e + m - 1), since log2 is concave and equals its
 * chord m - 1 at both ends. e + m - 1 is the float's bits less those of 1.0, over 2^23 (the difference, below 2^31
 * in magnitude, converts to float within 6e-8 relative; the power of two is exact); less the margin. Within
 * WALL_DETECTOR_LOG_BOUND_WIDTH of logf(y): loose, but the filter's test has far more room (a saturating evidence
 * mostly ends far beyond its bound).
 */
static inline float wall_detector_logf_lower_bound(float y)
{
  int32_t bits;
  memcpy(&bits, &y, sizeof(bits));
  const float e_plus_m_minus_1 = (float)(bits - 0x3f800000) * (1.f / (float)(1 << 23));
  return e_plus_m_minus_1 * 0.693147182f - WALL_DETECTOR_LOG_BOUND_MARGIN;
}

/** An upper bound of logf(y) for a positive normal y: the lower bound raised by its largest distance below logf. */
static inline float wall_detector_logf_upper_bound(float y)
{
  return wall_detector_logf_lower_bound(y) + WALL_DETECTOR_LOG_BOUND_WIDTH;
}

#ifdef __cplusplus
}
#endif

#endif /* WALL_DETECTOR_BOUNDS_H */
