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
 * @file math/pprz_algebra_float.h
 * Host stand-in for Paparazzi's float algebra types (same names and members).
 */

#ifndef PPRZ_ALGEBRA_FLOAT_H
#define PPRZ_ALGEBRA_FLOAT_H

struct FloatVect2 { float x, y; };
struct FloatVect3 { float x, y, z; };
struct FloatQuat { float qi, qx, qy, qz; };
/** Euler angles [rad] */
struct FloatEulers { float phi, theta, psi; };
/** Angular rates [rad/s] */
struct FloatRates { float p, q, r; };

#endif /* PPRZ_ALGEBRA_FLOAT_H */
