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
 * @file nps_arena_snapshot.c
 * Wall state as CSV (format in nps_arena_snapshot.h).
 */

#include "nps_arena_snapshot.h"
#include "nps_arena_params.h"
#include "nps_walls.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

int nps_arena_snapshot_header(FILE *f)
{
  return fputs("t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven\n", f) < 0
         ? -1 : 0;
}

/** Significant digits of the real columns (printf "%.9g": rest geometry to a nanometre, angles to 1e-7 deg). */
#define SNAPSHOT_DIGITS 9
/** Longest row: t (at most 63 characters), three ints (11), ten reals (16), separators. */
#define SNAPSHOT_ROW_LEN 400

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
 * Write x at out as printf("%.9g", x) does and return the length. Snapshots hold thousands of rows per
 * second for long walls, and glibc's exact decimal conversion made the snapshot the largest cost of a
 * 4000-plate run; this path scales x by a power of ten in one rounding (relative error 2^-53, at most
 * 1.1e-7 on the 9-digit integer) and rounds it, and leaves to sprintf every case where that could differ
 * from the exact conversion (within 1e-6 of a rounding tie), magnitudes beyond the exact powers of ten
 * (outside [1e-13, 1e31)) and the non-finite values. At most 16 characters ("-1.23456789e-308").
 */
static int format_g9(char *out, double x)
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
  int e = (int)floor(log10(ax));
  double m = scale10(ax, SNAPSHOT_DIGITS - 1 - e);
  if (m >= pow10_exact[SNAPSHOT_DIGITS]) {
    m = scale10(ax, SNAPSHOT_DIGITS - 1 - ++e);
  } else if (m < pow10_exact[SNAPSHOT_DIGITS - 1]) {
    m = scale10(ax, SNAPSHOT_DIGITS - 1 - --e);
  }
  const double whole = floor(m), frac = m - whole;   /* exact: whole >= m / 2 */
  if (!(m >= pow10_exact[SNAPSHOT_DIGITS - 1] && m < pow10_exact[SNAPSHOT_DIGITS]) || fabs(frac - 0.5) < 1e-6) {
    return sprintf(out, "%.9g", x);
  }
  unsigned long digits = (unsigned long)whole + (frac > 0.5);
  if (digits == (unsigned long)pow10_exact[SNAPSHOT_DIGITS]) {   /* 999999999.7 rounds to 1e9 */
    digits /= 10;
    e++;
  }
  char d[SNAPSHOT_DIGITS];
  for (int i = SNAPSHOT_DIGITS - 1; i >= 0; i--, digits /= 10) {
    d[i] = (char)('0' + digits % 10);
  }
  /* %g: exponent notation when the exponent is below -4 or at least the precision; then, or after the
   * point, trailing zeros are dropped (and the point with them) */
  const int scientific = e < -4 || e >= SNAPSHOT_DIGITS;
  const int point = scientific ? 0 : e;   /* index of the digit before the point, -1..-4: "0.000ddd" */
  int last = SNAPSHOT_DIGITS - 1;
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
static int format_int(char *out, int v)
{
  char tmp[12];
  unsigned u = v < 0 ? 0u - (unsigned)v : (unsigned)v;
  int n = 0;
  do {
    tmp[n++] = (char)('0' + u % 10u);
    u /= 10u;
  } while (u > 0u);
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

int nps_arena_snapshot_write(const struct nps_arena *a, FILE *f)
{
  char t_text[64], row[SNAPSHOT_ROW_LEN];
  const int t_len = snprintf(t_text, sizeof(t_text), "%.6f", a->time_s);
  if (t_len < 0 || t_len >= (int)sizeof(t_text)) {
    errno = ERANGE;
    return -1;
  }
  for (int i = 0; i < a->num_segments; i++) {
    const struct nps_wall_segment *s = &a->segs[i];
    const struct nps_wall *w = &a->walls[s->wall];
    const double L = w->p.hinge_height_m;
    const double real[10] = {
      s->a[0], s->a[1], s->b[0], s->b[1], w->n[0], w->n[1], s->angle_rad * 180. / M_PI,
      nps_walls_displacement_m(L, s->angle_rad, a->flight_height_m), L * sin(s->angle_rad), s->target_deg
    };
    char *p = row;
    memcpy(p, t_text, (size_t)t_len);
    p += t_len;
    *p++ = ',';
    p += format_int(p, s->wall);
    *p++ = ',';
    p += format_int(p, s->index);
    for (int k = 0; k < 10; k++) {
      *p++ = ',';
      p += format_g9(p, real[k]);
    }
    *p++ = ',';
    p += format_int(p, s->driven);
    *p++ = '\n';
    if (fwrite(row, 1, (size_t)(p - row), f) != (size_t)(p - row)) {
      return -1;
    }
  }
  return 0;
}

int nps_arena_snapshot_file(const struct nps_arena *a, const char *path, int append, char *err, size_t err_len)
{
  FILE *f = fopen(path, append ? "a" : "w");
  if (!f) {
    nps_arena_errf(err, err_len, path, 0, "cannot open for writing: %s", strerror(errno));
    return -1;
  }
  int rc = fseek(f, 0, SEEK_END) == 0 && ftell(f) == 0 ? nps_arena_snapshot_header(f) : 0;
  if (rc == 0) {
    rc = nps_arena_snapshot_write(a, f);
  }
  int saved = errno;
  if (fclose(f) != 0 && rc == 0) {
    saved = errno;
    rc = -1;
  }
  if (rc != 0) {
    nps_arena_errf(err, err_len, path, 0, "cannot write: %s", strerror(saved));
  }
  return rc;
}
