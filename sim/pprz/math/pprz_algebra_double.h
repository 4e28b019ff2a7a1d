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
 * @file math/pprz_algebra_double.h
 * Host stand-in for Paparazzi's double algebra types (same names and members).
 */

#ifndef PPRZ_ALGEBRA_DOUBLE_H
#define PPRZ_ALGEBRA_DOUBLE_H

struct DoubleVect3 { double x, y, z; };
struct DoubleQuat { double qi, qx, qy, qz; };
/** Euler angles [rad] */
struct DoubleEulers { double phi, theta, psi; };
/** Angular rates [rad/s] */
struct DoubleRates { double p, q, r; };

#endif /* PPRZ_ALGEBRA_DOUBLE_H */
