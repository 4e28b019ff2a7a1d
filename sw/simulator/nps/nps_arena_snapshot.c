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
#include "nps_csv.h"
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

/** Longest row: t (at most 63 characters), three ints (11), ten reals (16), separators. */
#define SNAPSHOT_ROW_LEN 400

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
    p += nps_csv_int(p, s->wall);
    *p++ = ',';
    p += nps_csv_int(p, s->index);
    for (int k = 0; k < 10; k++) {
      *p++ = ',';
      p += nps_csv_g9(p, real[k]);
    }
    *p++ = ',';
    p += nps_csv_int(p, s->driven);
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
