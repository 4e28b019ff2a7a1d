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
 * @file std.h
 * Host stand-in for Paparazzi's std.h: the integer types and the few macros our modules use.
 */

#ifndef STD_H
#define STD_H

#include <inttypes.h>
#include <stdbool.h>
#include <stddef.h>
#include <math.h>

#ifndef TRUE
#define TRUE true
#endif
#ifndef FALSE
#define FALSE false
#endif

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define Min(x, y) ((x) < (y) ? (x) : (y))
#define Max(x, y) ((x) > (y) ? (x) : (y))
#define Bound(_x, _min, _max) { if ((_x) > (_max)) (_x) = (_max); else if ((_x) < (_min)) (_x) = (_min); }
#define BoundAbs(_x, _max) Bound(_x, -(_max), (_max))
#define RadOfDeg(x) ((x) * (M_PI / 180.))
#define DegOfRad(x) ((x) * (180. / M_PI))

#endif /* STD_H */
