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

/** Most log files one spool holds rows for (the host spools readings.csv and detections.csv). */
#define NPS_CSV_SPOOL_FILES 4

/**
 * Rows a thread writes with nps_csv_write while it uses a spool are kept in memory, per file, until
 * nps_csv_spool_flush appends them: the host's worker threads spool the rows of their copters during a step
 * and the main thread appends the spools in copter order, so a log does not depend on the thread count.
 */
struct nps_csv_spool {
  struct nps_csv_spool_file {
    FILE *file;
    char *data;
    size_t len, cap;     ///< bytes held, bytes allocated
  } file[NPS_CSV_SPOOL_FILES];
  unsigned n_files;
  int failed;            ///< a row was lost (no memory, or more files than NPS_CSV_SPOOL_FILES)
};

/** The calling thread's nps_csv_write calls go to `spool` from now on; NULL (every thread's start): to the files. */
void nps_csv_spool_use(struct nps_csv_spool *spool);
/** Write `len` bytes of rows to f, or to the calling thread's spool if it uses one. */
void nps_csv_write(FILE *f, const char *rows, size_t len);
/** Append every file's spooled rows to it and empty the spool; -1 (errno ENOMEM) if rows were lost since the last flush. */
int nps_csv_spool_flush(struct nps_csv_spool *spool);
/** Release the spool's memory (its rows must have been flushed). */
void nps_csv_spool_free(struct nps_csv_spool *spool);

/** v in decimal. */
int nps_csv_int(char *out, long v);
/** x as printf("%.9g", x) writes it (exact path for common magnitudes, printf for the rest). */
int nps_csv_g9(char *out, double x);
/** x as printf("%.4f", x) writes it (exact decimal ties to even, as glibc); |x| >= 1e20 as "%.9g" (no row buffer
 * of NPS_CSV_NUMBER_LEN per number overflows). */
int nps_csv_fixed4(char *out, double x);

#endif /* NPS_CSV_H */
