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
 * @file nps_raycast_sonar.c
 * FINken sonar geometry: poses, boresight ray casts, and which other copters' sonars point at a sensor
 * (ctx_facing_sonars and the paths the cross-talk model needs).
 */

#include "nps_raycast.h"
#include "nps_arena_grid.h"
#include "nps_crosstalk.h"

#include <math.h>

/** Body-frame headings of the horizontal sonars [rad] (FINken layout: front, right, back, left). */
static const double sonar_heading_rad[4] = { 0., -M_PI / 2., M_PI, M_PI / 2. };

static const char *const sonar_names[NPS_SONAR_COUNT] = {
  "sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down"
};

const char *nps_sonar_name(enum nps_sonar sonar)
{
  return (unsigned)sonar < NPS_SONAR_COUNT ? sonar_names[sonar] : "";
}

void nps_raycast_sonar_pose(const struct nps_arena *a, const struct nps_arena_copter *c, enum nps_sonar sonar,
                            double origin_m[3], double dir[3])
{
  if (sonar == NPS_SONAR_DOWN) {
    dir[0] = 0.;
    dir[1] = 0.;
    dir[2] = -1.;
  } else {
    double psi = c->yaw_rad + sonar_heading_rad[sonar];
    dir[0] = cos(psi);
    dir[1] = sin(psi);
    dir[2] = 0.;
  }
  for (int k = 0; k < 3; k++) {
    origin_m[k] = c->pos_m[k] + a->sonar_offset_m * dir[k];
  }
}

enum nps_hit_kind nps_raycast_sonar(const struct nps_arena *a, const struct nps_arena_copter *c,
                                    enum nps_sonar sonar, double max_range_m, struct nps_ray_hit *hit)
{
  double o[3], d[3];
  nps_raycast_sonar_pose(a, c, sonar, o, d);
  return nps_raycast(a, o, d, max_range_m, c->id, NPS_RAYCAST_NO_ID, hit);
}

static double angle_between(const double u[3], const double v[3], double v_len)
{
  double cs = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / v_len;
  return acos(fmax(-1., fmin(1., cs)));
}

/** Insert f into out[0..*kept-1] sorted by path, keeping at most max_out. */
static void keep_nearest(struct nps_facing_sonar *out, int max_out, int *kept, const struct nps_facing_sonar *f)
{
  int i;
  if (*kept < max_out) {
    i = (*kept)++;
  } else if (out[max_out - 1].path_m > f->path_m) {
    i = max_out - 1; /* replaces the farthest */
  } else {
    return;
  }
  while (i > 0 && out[i - 1].path_m > f->path_m) {
    out[i] = out[i - 1];
    i--;
  }
  out[i] = *f;
}

/** Count (and collect) the sonars of copter q facing the receiver at p_r with boresight b_r. */
static int emitter_sonars(const struct nps_arena *a, const struct nps_arena_copter *q,
                          const struct nps_arena_copter *rx, const double p_r[3], const double b_r[3],
                          double half_angle_rad, double range_m, struct nps_facing_sonar *out, int max_out, int *kept)
{
  int count = 0;
  for (int s = 0; s < NPS_SONAR_COUNT; s++) {
    double p_e[3], b_e[3], dist;
    nps_raycast_sonar_pose(a, q, (enum nps_sonar)s, p_e, b_e);
    if (!nps_crosstalk_facing(p_r, b_r, p_e, b_e, half_angle_rad, range_m, &dist)) {
      continue;
    }
    count++;
    if (out && max_out > 0) {
      double w[3] = { p_r[0] - p_e[0], p_r[1] - p_e[1], p_r[2] - p_e[2] };
      double back[3] = { -w[0], -w[1], -w[2] };
      struct nps_facing_sonar f = {
        .copter_id = q->id, .sonar = (enum nps_sonar)s, .path_m = dist,
        .off_axis_rad = angle_between(b_e, w, dist), .rx_off_axis_rad = angle_between(b_r, back, dist),
        .blocked = nps_raycast_line_blocked(a, p_e, p_r, q->id, rx->id, NULL)
      };
      keep_nearest(out, max_out, kept, &f);
    }
  }
  return count;
}

struct facing_search {
  const struct nps_arena *a;
  const struct nps_arena_copter *rx;
  double p_r[3], b_r[3];
  double half_angle_rad, range_m;
  struct nps_facing_sonar *out;
  int max_out, kept, count;
};

/**
 * Whether the receiver can face any sonar of copter q. With the sonars at the copter centre (offset 0) every
 * sonar of q sits at q's centre, so the receiver's half of the facing test (q within its cone and range) is
 * one test for all five: nps_crosstalk_facing with an emitter pointing straight back at the receiver, which
 * passes the emitter's half by construction. With an offset, each sonar is tested on its own.
 */
static int may_face(const struct facing_search *f, const struct nps_arena_copter *q)
{
  if (f->a->sonar_offset_m != 0.) {
    return 1;
  }
  const double back[3] = { f->p_r[0] - q->pos_m[0], f->p_r[1] - q->pos_m[1], f->p_r[2] - q->pos_m[2] };
  double dist_m;
  return nps_crosstalk_facing(f->p_r, f->b_r, q->pos_m, back, f->half_angle_rad, f->range_m, &dist_m);
}

static void visit_emitter(void *ctx, const struct nps_arena_copter *q)
{
  struct facing_search *f = ctx;
  if (q->id != f->rx->id && may_face(f, q)) {
    f->count += emitter_sonars(f->a, q, f->rx, f->p_r, f->b_r, f->half_angle_rad, f->range_m, f->out, f->max_out,
                               &f->kept);
  }
}

/**
 * Box [xlo, ylo, xhi, yhi] [m] holding the ground track of the receiver's beam (half-angle theta < 90 deg):
 * - horizontal beam: the cone projects into the 2D sector of the same half-angle and radius (a direction v
 *   within theta of a horizontal b has |v_side| <= sin(theta) <= tan(theta) v_along), whose box spans the
 *   apex, the two edge ends and the ends of the axis directions inside the sector;
 * - vertical beam (down sonar): the disc of radius range sin(theta) around the apex;
 * - other beams and wide cones: the square of half-side range.
 * Grown by `grow_m`.
 */
static void beam_box(const double p[3], const double b[3], double half_angle_rad, double range_m, double grow_m,
                     double box[4])
{
  box[0] = p[0] - range_m;
  box[1] = p[1] - range_m;
  box[2] = p[0] + range_m;
  box[3] = p[1] + range_m;
  if (b[0] == 0. && b[1] == 0. && half_angle_rad < M_PI / 2.) {
    const double r = range_m * sin(half_angle_rad);
    box[0] = p[0] - r;
    box[1] = p[1] - r;
    box[2] = p[0] + r;
    box[3] = p[1] + r;
  } else if (b[2] == 0. && half_angle_rad < M_PI / 2.) {
    const double cs = cos(half_angle_rad), sn = sin(half_angle_rad), r = range_m / hypot(b[0], b[1]);
    const double ends[2][2] = { { b[0] * cs - b[1] * sn, b[0] * sn + b[1] * cs },
                                { b[0] * cs + b[1] * sn, -b[0] * sn + b[1] * cs } };
    box[0] = box[2] = p[0];
    box[1] = box[3] = p[1];
    for (int k = 0; k < 2; k++) {
      box[0] = fmin(box[0], p[0] + r * ends[k][0]);
      box[2] = fmax(box[2], p[0] + r * ends[k][0]);
      box[1] = fmin(box[1], p[1] + r * ends[k][1]);
      box[3] = fmax(box[3], p[1] + r * ends[k][1]);
    }
    const double axis_cos = cs * hypot(b[0], b[1]);  /* unit axis e is inside when e . b >= cos(theta) |b| */
    box[0] = -b[0] >= axis_cos ? p[0] - range_m : box[0];
    box[2] = b[0] >= axis_cos ? p[0] + range_m : box[2];
    box[1] = -b[1] >= axis_cos ? p[1] - range_m : box[1];
    box[3] = b[1] >= axis_cos ? p[1] + range_m : box[3];
  }
  box[0] -= grow_m;
  box[1] -= grow_m;
  box[2] += grow_m;
  box[3] += grow_m;
}

int nps_raycast_facing_sonars(const struct nps_arena *a, const struct nps_arena_copter *rx, enum nps_sonar rx_sonar,
                              double half_angle_rad, double range_m, struct nps_facing_sonar *out, int max_out)
{
  struct facing_search f = {
    .a = a, .rx = rx, .half_angle_rad = half_angle_rad, .range_m = range_m, .out = out, .max_out = max_out,
  };
  nps_raycast_sonar_pose(a, rx, rx_sonar, f.p_r, f.b_r);
  /* an emitting sonar is within the beam; the centre of its copter within the sonar offset of it */
  double box[4];
  beam_box(f.p_r, f.b_r, half_angle_rad, range_m, fabs(a->sonar_offset_m) + NPS_ARENA_GRID_PAD_M, box);
  nps_arena_grid_copters_in_box(a, box[0], box[1], box[2], box[3], visit_emitter, &f);
  return f.count;
}
