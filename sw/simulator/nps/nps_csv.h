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
 * @file nps_csv.h
 * Fast number formatting for the simulator's CSV logs: printf's decimal conversion was the largest cost of a
 * simulation with its logs on. Each function writes at out (NUL-terminated) and returns the length.
 */

#ifndef NPS_CSV_H
#define NPS_CSV_H

#include <stdio.h>

/** Longest text of one number from these functions, NUL included. */
#define NPS_CSV_NUMBER_LEN 32

/** stdio buffer of a log [bytes]: one write call per MiB instead of per page. */
#define NPS_CSV_BUFFER_LEN (1 << 20)

/** fopen(path, "w") with a buffer of NPS_CSV_BUFFER_LEN in *buffer (NULL if none could be had): free it after fclose. */
FILE *nps_csv_fopen(const char *path, char **buffer);

/** v in decimal. */
int nps_csv_int(char *out, long v);
/** x as printf("%.9g", x) writes it (exact path for common magnitudes, printf for the rest). */
int nps_csv_g9(char *out, double x);
/** x as printf("%.4f", x) writes it, but for exact decimal ties (rounded away from zero here). */
int nps_csv_fixed4(char *out, double x);

#endif /* NPS_CSV_H */
