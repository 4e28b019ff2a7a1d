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
 * @file nps_error.h
 * Error messages of the simulator libraries: a caller's buffer receives "file:line: reason" style text
 * (the libraries return -1 or NULL and never print).
 */

#ifndef NPS_ERROR_H
#define NPS_ERROR_H

#include <stdarg.h>
#include <stddef.h>

/** printf into err (err_len bytes, always NUL-terminated); nothing when err is NULL or err_len 0. */
void nps_error_set(char *err, size_t err_len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/** The same with a va_list, for functions that take a format themselves. */
void nps_error_vset(char *err, size_t err_len, const char *fmt, va_list ap) __attribute__((format(printf, 3, 0)));

#endif /* NPS_ERROR_H */
