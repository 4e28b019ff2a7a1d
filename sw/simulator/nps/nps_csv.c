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
 * @file nps_csv.c
 * Fast number formatting for the simulator's CSV logs (see nps_csv.h).
 */

#include "nps_csv.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Significant digits of nps_csv_g9 (printf "%.9g"). */
#define NPS_CSV_G_DIGITS 9

/** 10^k for k = 0 .. 22, all exact in a double. */
static const double pow10_exact[23] = {
  1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19,
  1e20, 1e21, 1e22
};

/** x * 10^shift in one rounding (a multiplication or a division by an exact power of ten). */
static double scale10(double x, int shift)
{
  return shift >= 0 ? x * pow10_exact[shift] : x / pow10_exact[-shift];
}

/**
 * Write x at out as printf("%.9g", x) does and return the length. Logs hold thousands of rows per
 * second, and glibc's exact decimal conversion made them the largest cost of a simulation; this path scales x by a power of ten in one rounding (relative error 2^-53, at most
 * 1.1e-7 on the 9-digit integer) and rounds it, and leaves to sprintf every case where that could differ
 * from the exact conversion (within 1e-6 of a rounding tie), magnitudes beyond the exact powers of ten
 * (outside [1e-13, 1e31)) and the non-finite values. At most 16 characters ("-1.23456789e-308").
 */
int nps_csv_g9(char *out, double x)
{
  const double ax = fabs(x);
  char *p = out;
  if (signbit(x)) {
    *p++ = '-';
  }
  if (ax == 0.) {
    *p++ = '0';
    *p = '\0';
    return (int)(p - out);
  }
  if (!(ax >= 1e-13 && ax < 1e31)) {
    return sprintf(out, "%.9g", x);
  }
  /* decimal exponent from the binary one (ax = f 2^b, f in [0.5, 1)): log10(ax) lies in [(b - 1) log10(2),
   * b log10(2)), narrower than 1, so this is floor(log10(ax)) or one less, which the test below corrects;
   * the digits come from the scaling, so the text does not depend on this first guess (and log10 is slow) */
  int b;
  frexp(ax, &b);
  int e = (int)floor((b - 1) * 0.30102999566398120);
  double m = scale10(ax, NPS_CSV_G_DIGITS - 1 - e);
  if (m >= pow10_exact[NPS_CSV_G_DIGITS]) {
    m = scale10(ax, NPS_CSV_G_DIGITS - 1 - ++e);
  } else if (m < pow10_exact[NPS_CSV_G_DIGITS - 1]) {
    m = scale10(ax, NPS_CSV_G_DIGITS - 1 - --e);
  }
  const double whole = floor(m), frac = m - whole;   /* exact: whole >= m / 2 */
  if (!(m >= pow10_exact[NPS_CSV_G_DIGITS - 1] && m < pow10_exact[NPS_CSV_G_DIGITS]) || fabs(frac - 0.5) < 1e-6) {
    return sprintf(out, "%.9g", x);
  }
  unsigned long digits = (unsigned long)whole + (frac > 0.5);
  if (digits == (unsigned long)pow10_exact[NPS_CSV_G_DIGITS]) {   /* 999999999.7 rounds to 1e9 */
    digits /= 10;
    e++;
  }
  char d[NPS_CSV_G_DIGITS];
  for (int i = NPS_CSV_G_DIGITS - 1; i >= 0; i--, digits /= 10) {
    d[i] = (char)('0' + digits % 10);
  }
  /* %g: exponent notation when the exponent is below -4 or at least the precision; then, or after the
   * point, trailing zeros are dropped (and the point with them) */
  const int scientific = e < -4 || e >= NPS_CSV_G_DIGITS;
  const int point = scientific ? 0 : e;   /* index of the digit before the point, -1..-4: "0.000ddd" */
  int last = NPS_CSV_G_DIGITS - 1;
  while (last > point && last > 0 && d[last] == '0') {
    last--;
  }
  if (point < 0) {
    *p++ = '0';
    *p++ = '.';
    for (int i = -1; i > point; i--) {
      *p++ = '0';
    }
  }
  for (int i = 0; i <= last; i++) {
    *p++ = d[i];
    if (i == point && i < last) {
      *p++ = '.';
    }
  }
  if (scientific) {
    *p++ = 'e';
    *p++ = e < 0 ? '-' : '+';
    const int ae = e < 0 ? -e : e;
    *p++ = (char)('0' + ae / 10);
    *p++ = (char)('0' + ae % 10);
  }
  *p = '\0';
  return (int)(p - out);
}

/** Write v in decimal at out and return the length. */
int nps_csv_int(char *out, long v)
{
  char tmp[24];
  unsigned long u = v < 0 ? 0ul - (unsigned long)v : (unsigned long)v;
  int n = 0;
  do {
    tmp[n++] = (char)('0' + u % 10ul);
    u /= 10ul;
  } while (u > 0ul);
  char *p = out;
  if (v < 0) {
    *p++ = '-';
  }
  while (n > 0) {
    *p++ = tmp[--n];
  }
  *p = '\0';
  return (int)(p - out);
}

FILE *nps_csv_fopen(const char *path, char **buffer)
{
  FILE *f = fopen(path, "w");
  *buffer = f != NULL ? malloc(NPS_CSV_BUFFER_LEN) : NULL;
  if (*buffer != NULL && setvbuf(f, *buffer, _IOFBF, NPS_CSV_BUFFER_LEN) != 0) {
    free(*buffer);
    *buffer = NULL;
  }
  return f;
}

int nps_csv_fixed4(char *out, double x)
{
  /* above 9e11, printf itself while "%.4f" fits the buffer (|x| < 1e20: 20 digits, point, 4 decimals, sign), "%.9g"
   * beyond */
  if (!(fabs(x) < 9e11)) {
    return snprintf(out, NPS_CSV_NUMBER_LEN, fabs(x) < 1e20 ? "%.4f" : "%.9g", x);
  }
  /* x * 1e4 rounded to the nearest integer as printf rounds the exact value of x (ties to even): r = fl(x * 1e4)
   * < 2^53 may be off by half an ulp, which fma gives exactly (err = x * 1e4 - r); r - n is exact, so the exact
   * product lies d = r - n + err from n (d is exact where it matters: at +-0.5 and beyond) */
  const double r = x * 1e4;
  const double err = fma(x, 1e4, -r);
  long long scaled = llround(r);
  const double d = (r - (double)scaled) + err;
  if (d > 0.5 || (d == 0.5 && (scaled & 1))) {
    scaled++;
  } else if (d < -0.5 || (d == -0.5 && (scaled & 1))) {
    scaled--;
  }
  const unsigned long long a = scaled < 0 ? 0ull - (unsigned long long)scaled : (unsigned long long)scaled;
  char *p = out;
  if (scaled < 0 || (scaled == 0 && signbit(x))) {
    *p++ = '-';
  }
  p += nps_csv_int(p, (long)(a / 10000ull));
  *p++ = '.';
  const unsigned frac = (unsigned)(a % 10000ull);
  *p++ = (char)('0' + frac / 1000u);
  *p++ = (char)('0' + frac / 100u % 10u);
  *p++ = (char)('0' + frac / 10u % 10u);
  *p++ = (char)('0' + frac % 10u);
  *p = '\0';
  return (int)(p - out);
}

/** The spool of the calling thread, NULL: rows go straight to the files. */
static __thread struct nps_csv_spool *thread_spool;

void nps_csv_spool_use(struct nps_csv_spool *spool)
{
  thread_spool = spool;
}

/** The spool's buffer for f (added on f's first row), NULL if the spool has no room for another file. */
static struct nps_csv_spool_file *spool_file(struct nps_csv_spool *spool, FILE *f)
{
  for (unsigned i = 0; i < spool->n_files; i++) {
    if (spool->file[i].file == f) {
      return &spool->file[i];
    }
  }
  if (spool->n_files == NPS_CSV_SPOOL_FILES) {
    return NULL;
  }
  struct nps_csv_spool_file *sf = &spool->file[spool->n_files++];
  *sf = (struct nps_csv_spool_file) { .file = f };
  return sf;
}

void nps_csv_write(FILE *f, const char *rows, size_t len)
{
  struct nps_csv_spool *spool = thread_spool;
  if (spool == NULL) {
    fwrite(rows, 1, len, f);
    return;
  }
  struct nps_csv_spool_file *sf = spool_file(spool, f);
  if (sf != NULL && sf->len + len > sf->cap) {
    const size_t cap = 2 * (sf->len + len) > 4096 ? 2 * (sf->len + len) : 4096;
    char *data = realloc(sf->data, cap);
    if (data == NULL) {
      sf = NULL;
    } else {
      sf->data = data;
      sf->cap = cap;
    }
  }
  if (sf == NULL) {
    spool->failed = 1;
    return;
  }
  memcpy(sf->data + sf->len, rows, len);
  sf->len += len;
}

int nps_csv_spool_flush(struct nps_csv_spool *spool)
{
  for (unsigned i = 0; i < spool->n_files; i++) {
    struct nps_csv_spool_file *sf = &spool->file[i];
    if (sf->len > 0) {
      fwrite(sf->data, 1, sf->len, sf->file);
      sf->len = 0;
    }
  }
  if (spool->failed) {
    spool->failed = 0;
    errno = ENOMEM;
    return -1;
  }
  return 0;
}

void nps_csv_spool_free(struct nps_csv_spool *spool)
{
  for (unsigned i = 0; i < spool->n_files; i++) {
    free(spool->file[i].data);
  }
  *spool = (struct nps_csv_spool) { .n_files = 0 };
}
