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
 * @file nps_error.c
 * Error messages of the simulator libraries (see nps_error.h).
 */

#include "nps_error.h"

#include <stdarg.h>
#include <stdio.h>

void nps_error_vset(char *err, size_t err_len, const char *fmt, va_list ap)
{
  if (err != NULL && err_len > 0) {
    vsnprintf(err, err_len, fmt, ap);
  }
}

void nps_error_set(char *err, size_t err_len, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  nps_error_vset(err, err_len, fmt, ap);
  va_end(ap);
}
