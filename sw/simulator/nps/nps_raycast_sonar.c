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

static const char *const sonar_names[NPS_SONAR_COUNT] = {
  "sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down"
};

const char *nps_sonar_name(enum nps_sonar sonar)
{
  return (unsigned)sonar < NPS_SONAR_COUNT ? sonar_names[sonar] : "";
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
static inline void keep_nearest(struct nps_facing_sonar *out, int max_out, int *kept, const struct nps_facing_sonar *f)
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

/** The receiver as the quick rejection of every emitter reads it (centred_emitter). */
struct receiver_beam {
  double p_r[3], b_r[3];
  double cos_half;
  double range2_loose;     /* range_m^2 (1 + 1e-6): the root-free range test */
  double cos2_loose;       /* cos_half^2 (1 - 1e-6): the root-free cone test */
};

struct facing_search {
  const struct nps_arena *a;
  int rx_id;
  struct receiver_beam beam;
  double range_m;
  int with_dir;            /* 1: entries carry the emitter's boresight (nps_raycast_facing_sonars) */
  struct nps_facing_sonar *out;
  int max_out, kept, count;
};

/** Count the facing emitter e and keep it if among the nearest. */
static inline void found_facing(struct facing_search *f, const struct nps_facing_sonar *e)
{
  f->count++;
  if (f->out && f->max_out > 0) {
    keep_nearest(f->out, f->max_out, &f->kept, e);
  }
}

/** Margin [-] of the cheap emitter test on the cosine of the off-axis angle (see centred_emitter_sonars). */
#define EMITTER_MARGIN 1e-12

/**
 * The sonars of copter q facing the receiver when the sonars are at the copter centre (offset 0): every sonar
 * of q sits at q's centre, so the receiver's half of the facing test (q within its cone and range) and the
 * path, dist_m, are shared by all five, which were tested already (visit_emitter).
 * Each sonar's own half is first a cheap test: the exact test nps_crosstalk_in_cone(b, to_rx, dist_m, cos_half),
 * with the boresight b of nps_raycast_sonar_pose, divides b . to_rx by |b| dist_m, where |b| = 1 within a few ulp;
 * the cheap one compares b . to_rx with cos_half dist_m: their cosines differ by a few ulp, far below the margin.
 * So a cosine below cos_half - margin fails the exact test, one at or above cos_half + margin passes it, and only
 * one in between needs it (or to report the boresight). The horizontal boresights are (cos yaw, sin yaw) turned
 * by quarter turns (nps_raycast_sonar_pose), so their b . to_rx are two dot products and their negations, the
 * same numbers.
 */
static void centred_emitter_sonars(struct facing_search *f, const struct nps_arena_copter *q, const double to_rx[3],
                                   double dist_m)
{
  double cos_yaw, sin_yaw;
  nps_arena_copter_yaw_trig(q, &cos_yaw, &sin_yaw);
  /* front (cos, sin) and right (sin, -cos) along to_rx; back and left point the other way; down is (0, 0, -1) */
  const double ahead_m = cos_yaw * to_rx[0] + sin_yaw * to_rx[1], aside_m = sin_yaw * to_rx[0] - cos_yaw * to_rx[1];
  const double along_m[NPS_SONAR_COUNT] = { ahead_m, aside_m, -ahead_m, -aside_m, -to_rx[2] };
  const double surely_out_m = (f->beam.cos_half - EMITTER_MARGIN) * dist_m;
  const double surely_in_m = (f->beam.cos_half + EMITTER_MARGIN) * dist_m;
  for (int s = 0; s < NPS_SONAR_COUNT; s++) {
    if (along_m[s] < surely_out_m) {
      continue;
    }
    const enum nps_sonar sonar = (enum nps_sonar)s;
    struct nps_facing_sonar e = {
      .copter_id = q->id, .sonar = sonar, .path_m = dist_m,
      .emitter_pos_m = { q->pos_m[0], q->pos_m[1], q->pos_m[2] }, .emitter_dir = { NAN, NAN, NAN },
      .off_axis_rad = NAN, .rx_off_axis_rad = NAN, .blocked = -1
    };
    if (along_m[s] < surely_in_m || f->with_dir) {
      nps_raycast_sonar_pose(f->a, q, sonar, e.emitter_pos_m, e.emitter_dir);
      if (!nps_crosstalk_in_cone(e.emitter_dir, to_rx, dist_m, f->beam.cos_half)) {
        continue;
      }
    }
    found_facing(f, &e);
  }
}

/** The sonars of copter q facing the receiver when the sonars sit off the centre: each one on its own. */
static void offset_emitter_sonars(struct facing_search *f, const struct nps_arena_copter *q)
{
  for (int s = 0; s < NPS_SONAR_COUNT; s++) {
    struct nps_facing_sonar e = {
      .copter_id = q->id, .sonar = (enum nps_sonar)s, .emitter_dir = { NAN, NAN, NAN }, .off_axis_rad = NAN,
      .rx_off_axis_rad = NAN, .blocked = -1
    };
    double dir[3];
    nps_raycast_sonar_pose(f->a, q, (enum nps_sonar)s, e.emitter_pos_m, dir);
    if (nps_crosstalk_facing_cos(f->beam.p_r, f->beam.b_r, e.emitter_pos_m, dir, f->beam.cos_half, f->range_m,
                                 &e.path_m)) {
      for (int k = 0; f->with_dir && k < 3; k++) {
        e.emitter_dir[k] = dir[k];
      }
      found_facing(f, &e);
    }
  }
}

/**
 * Cosines of half-angles up to which the emitter's half of nps_crosstalk_facing_cos, for an emitter pointing straight
 * back at the receiver (dir = to_rx, |to_rx| = dist_m), surely passes: it tests (to_rx . to_rx) / (dist_m dist_m)
 * >= cos_half, where dist_m = sqrt(to_rx . to_rx) is rounded the same way, so the quotient is 1 within 4 ulp.
 */
#define BACK_POINTING_PASSES_COS (1. - 1e-12)

/**
 * The exact receiver's half of the facing test for copter q (past centred_emitter's rejection), then its sonars:
 * nps_crosstalk_facing_cos(p_r, b_r, q's centre, to_rx, ...) with the same operations, the emitter's half
 * skipped where it surely passes.
 */
static __attribute__((noinline)) void centred_emitter_exact(struct facing_search *f, const struct nps_arena_copter *q,
                                                            double to_q2)
{
  const double *p_r = f->beam.p_r;
  const double to_rx[3] = { p_r[0] - q->pos_m[0], p_r[1] - q->pos_m[1], p_r[2] - q->pos_m[2] };
  const double to_q[3] = { -to_rx[0], -to_rx[1], -to_rx[2] }, dist_m = sqrt(to_q2);
  if (dist_m <= f->range_m && nps_crosstalk_in_cone(f->beam.b_r, to_q, dist_m, f->beam.cos_half) &&
      (f->beam.cos_half <= BACK_POINTING_PASSES_COS || nps_crosstalk_in_cone(to_rx, to_rx, dist_m, f->beam.cos_half))) {
    centred_emitter_sonars(f, q, to_rx, dist_m);
  }
}

/**
 * Count (and keep the nearest of) the sonars of copter q (not the receiver) facing the receiver, the sonars at
 * the centre: the receiver's half of the test is done once for q, first without a root or a division (beyond
 * the range, or off the axis, q cannot be in the cone: the exact test, dist <= range and (b . to) >= cos |to|
 * for a unit b, with a millionth to spare for rounding), then exactly, as nps_crosstalk_facing with an emitter
 * pointing straight back at the receiver, which passes the emitter's half by construction. Always inlined: the
 * quick rejection runs for every candidate, on the receiver's beam (a copy the caller's loop keeps in registers:
 * the search itself goes to calls).
 */
static inline __attribute__((always_inline)) void centred_emitter(struct facing_search *f,
                                                                  const struct receiver_beam *beam,
                                                                  const struct nps_arena_copter *q)
{
  const double to_rx[3] = { beam->p_r[0] - q->pos_m[0], beam->p_r[1] - q->pos_m[1], beam->p_r[2] - q->pos_m[2] };
  const double along = -(beam->b_r[0] * to_rx[0] + beam->b_r[1] * to_rx[1] + beam->b_r[2] * to_rx[2]);
  if (beam->cos_half > 0. && along < 0.) {   /* behind the receiver (about half the copters): no distance needed */
    return;
  }
  const double to_q2 = to_rx[0] * to_rx[0] + to_rx[1] * to_rx[1] + to_rx[2] * to_rx[2];
  if (to_q2 > beam->range2_loose || (beam->cos_half > 0. && along * along < beam->cos2_loose * to_q2)) {
    return;
  }
  centred_emitter_exact(f, q, to_q2);
}

/** Count (and keep the nearest of) the sonars of copter q facing the receiver (a grid query's visitor). */
static void visit_emitter(void *ctx, const struct nps_arena_copter *q)
{
  struct facing_search *f = ctx;
  if (q->id == f->rx_id) {
    return;
  }
  if (f->a->sonar_offset_m != 0.) {
    offset_emitter_sonars(f, q);
  } else {
    centred_emitter(f, &f->beam, q);
  }
}

/**
 * visit_emitter for every copter, in index order (the grid's scan goes in cell order: the same entries, of which
 * only two at exactly the same path could swap), with the choice of the sonars' placement made once.
 */
static void visit_all_emitters(struct facing_search *f)
{
  const struct nps_arena_copter *const copters = f->a->copters;
  const int n = f->a->num_copters, rx_id = f->rx_id;
  if (f->a->sonar_offset_m == 0.) {
    const struct receiver_beam beam = f->beam;
    for (int i = 0; i < n; i++) {
      if (copters[i].id != rx_id) {
        centred_emitter(f, &beam, &copters[i]);
      }
    }
  } else {
    for (int i = 0; i < n; i++) {
      if (copters[i].id != rx_id) {
        offset_emitter_sonars(f, &copters[i]);
      }
    }
  }
}

/**
 * Box [xlo, ylo, xhi, yhi] [m] holding the ground track of the receiver's beam (unit boresight b, cone of
 * cosine cos_half):
 * - horizontal beam, half-angle theta < 90 deg: the cone projects into the 2D sector of the same half-angle
 *   and radius (a direction v within theta of a horizontal b has |v_side| <= sin(theta) <= tan(theta)
 *   v_along), whose box spans the apex, the two edge ends and the ends of the axis directions inside the
 *   sector;
 * - vertical beam (down sonar), theta < 90 deg: the disc of radius range sin(theta) around the apex;
 * - other beams and wide cones: the square of half-side range.
 * Grown by `grow_m`. Only which copters get the exact test depends on the box, never the result, so it is
 * computed loosely: sin(theta) from cos(theta), |b| taken as 1, axes included with a tolerance, and all
 * grown by a millionth of the range.
 */
static void beam_box(const double p[3], const double b[3], double cos_half, double range_m, double grow_m,
                     double box[4])
{
  const double cs = cos_half, sn = sqrt(cs * cs < 1. ? 1. - cs * cs : 0.), tol = 1e-9;
  box[0] = p[0] - range_m;
  box[1] = p[1] - range_m;
  box[2] = p[0] + range_m;
  box[3] = p[1] + range_m;
  if (b[0] == 0. && b[1] == 0. && cs > 0.) {
    const double r = range_m * sn;
    box[0] = p[0] - r;
    box[1] = p[1] - r;
    box[2] = p[0] + r;
    box[3] = p[1] + r;
  } else if (b[2] == 0. && cs > 0.) {
    const double ends[2][2] = { { b[0] * cs - b[1] * sn, b[0] * sn + b[1] * cs },
                                { b[0] * cs + b[1] * sn, -b[0] * sn + b[1] * cs } };
    box[0] = box[2] = p[0];
    box[1] = box[3] = p[1];
    for (int k = 0; k < 2; k++) {
      const double x = p[0] + range_m * ends[k][0], y = p[1] + range_m * ends[k][1];
      box[0] = x < box[0] ? x : box[0];
      box[2] = x > box[2] ? x : box[2];
      box[1] = y < box[1] ? y : box[1];
      box[3] = y > box[3] ? y : box[3];
    }
    /* unit axis e is inside the sector when e . b >= cos(theta) */
    box[0] = -b[0] >= cs - tol ? p[0] - range_m : box[0];
    box[2] = b[0] >= cs - tol ? p[0] + range_m : box[2];
    box[1] = -b[1] >= cs - tol ? p[1] - range_m : box[1];
    box[3] = b[1] >= cs - tol ? p[1] + range_m : box[3];
  }
  grow_m += 1e-6 * range_m;
  box[0] -= grow_m;
  box[1] -= grow_m;
  box[2] += grow_m;
  box[3] += grow_m;
}

/** The search of nps_raycast_facing_nearest; with_dir = 1 also reports each emitter's boresight. */
static int search_facing(const struct nps_arena *a, int rx_id, const double p_r[3], const double b_r[3],
                         double cos_half_angle, double range_m, int with_dir, struct nps_facing_sonar *out,
                         int max_out)
{
  /* every member named: a partly named struct is zeroed by `rep stos` first, slow to start on x86-64 */
  struct facing_search f = {
    .a = a, .rx_id = rx_id,
    .beam = {
      .p_r = { p_r[0], p_r[1], p_r[2] }, .b_r = { b_r[0], b_r[1], b_r[2] }, .cos_half = cos_half_angle,
      .range2_loose = range_m * range_m * (1. + 1e-6), .cos2_loose = cos_half_angle * cos_half_angle * (1. - 1e-6)
    },
    .range_m = range_m, .with_dir = with_dir, .out = out,
    .max_out = max_out, .kept = 0, .count = 0
  };
  if (nps_arena_grid_few_copters(a->grid)) {   /* a few copters: the beam's box would hold most of them */
    visit_all_emitters(&f);
  } else {
    /* an emitting sonar is within the beam; the centre of its copter within the sonar offset of it */
    double box[4];
    beam_box(f.beam.p_r, f.beam.b_r, cos_half_angle, range_m, fabs(a->sonar_offset_m) + NPS_ARENA_GRID_PAD_M, box);
    nps_arena_grid_copters_in_box(a, box[0], box[1], box[2], box[3], visit_emitter, &f);
  }
  return f.count;
}

int nps_raycast_facing_nearest(const struct nps_arena *a, int rx_id, const double p_r[3], const double b_r[3],
                               double cos_half_angle, double range_m, struct nps_facing_sonar *out, int max_out)
{
  return search_facing(a, rx_id, p_r, b_r, cos_half_angle, range_m, 0, out, max_out);
}

int nps_raycast_facing_sonars(const struct nps_arena *a, const struct nps_arena_copter *rx, enum nps_sonar rx_sonar,
                              double half_angle_rad, double range_m, struct nps_facing_sonar *out, int max_out)
{
  double p_r[3], b_r[3];
  nps_raycast_sonar_pose(a, rx, rx_sonar, p_r, b_r);
  const int count = search_facing(a, rx->id, p_r, b_r, cos(half_angle_rad), range_m, 1, out, max_out);
  for (int i = 0; out != NULL && i < count && i < max_out; i++) {
    struct nps_facing_sonar *e = &out[i];
    const double w[3] = { p_r[0] - e->emitter_pos_m[0], p_r[1] - e->emitter_pos_m[1], p_r[2] - e->emitter_pos_m[2] };
    const double back[3] = { -w[0], -w[1], -w[2] };
    e->off_axis_rad = angle_between(e->emitter_dir, w, e->path_m);
    e->rx_off_axis_rad = angle_between(b_r, back, e->path_m);
    e->blocked = nps_raycast_line_blocked(a, e->emitter_pos_m, p_r, e->copter_id, rx->id, NULL);
  }
  return count;
}
