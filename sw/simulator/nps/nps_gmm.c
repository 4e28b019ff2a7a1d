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
 * @file nps_gmm.c
 * Conditional Gaussian mixture: validation, conditioning in log space, exact and alias-table sampling.
 * Formulas in nps_gmm.h.
 */

#include "nps_gmm.h"
#include "nps_error.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>

/** Grid half-width beyond the outermost component means [standard deviations of the true range]. */
#define NPS_GMM_GRID_SIGMAS 6.0
/** Cells per smallest true-range standard deviation: keeps the proposal bound tight (acceptance > ~90%). */
#define NPS_GMM_CELLS_PER_SIGMA 4.0
#define NPS_GMM_MIN_CELLS 16
#define NPS_GMM_MAX_CELLS 4096
/** |correlation| at or above 1 - this is a singular covariance. */
#define NPS_GMM_SINGULAR_TOL 1e-12
/**
 * Proposals a draw in a cell makes before it takes the exact O(K) method instead: the same law (each proposal is
 * accepted or not independently), but bounded where the cells are too wide for their bounds (a component 1e36 m
 * wide stretches the grid so far that a draw at 40 m accepted once in 1e37 proposals). Where the bounds are tight,
 * as the grid makes them, 64 proposals in a row are never all rejected.
 */
#define NPS_GMM_MAX_PROPOSALS 64

/** Per-component values the samplers use, precomputed. */
struct nps_gmm_comp {
  double mu_t;        /**< mean of the true range [m] */
  double inv_2var_t;  /**< 1 / (2 s_tt) [1/m^2] */
  double log_norm;    /**< log phi_i - log(2 pi s_tt) / 2 */
  double mu_m;        /**< mean of the measured range [m] */
  double slope;       /**< s_tm / s_tt (regression of measured on true) */
  double sd;          /**< conditional standard deviation sqrt(s_mm - s_tm^2 / s_tt) [m] */
};

/**
 * Column c of a cell's Walker alias table in 8 bytes, so that a draw reads one small entry of a table that
 * stays in cache. The table is gsl_ran_discrete_preproc()'s: column c keeps c when u < F[c], else proposes its
 * alias A[c] (GSL stores F[c] as (c + probability of keeping c) / K, Knuth's convention); propose() decides
 * exactly as gsl_ran_discrete() does, with the same uniform. The entry holds F[c] and the squeezes rounded
 * down; the exact values (struct nps_gmm threshold, squeeze) are read only when the rounded ones cannot decide.
 */
struct nps_gmm_alias {
  float keep_below;         /**< F[c] rounded down to a float */
  uint16_t alias;           /**< A[c] (< NPS_GMM_MAX_COMPONENTS) */
  uint8_t squeeze_own;      /**< squeeze of c rounded down to a multiple of 1/256 [1/256] */
  uint8_t squeeze_alias;    /**< the same for A[c] */
};

/** Whether a cell's alias table is built (cell_ready). */
enum nps_gmm_cell_state { NPS_GMM_CELL_UNBUILT = 0, NPS_GMM_CELL_BUILT, NPS_GMM_CELL_FAILED };

/**
 * What builds the cells' tables, each on the first draw at a true range in it: a run only ever draws on the
 * true ranges its sensors meet (the default ranging mixture's grid spans -1.7 to 4.2 m, the ranging chain draws
 * on 0 to 2.5 m), so building every cell at load would spend most of a short run's time on cells it never uses.
 * Draws in several threads may ask for the same cell at once: one builds it under the lock and publishes its state
 * with release ordering, which a draw reads with acquire ordering before it reads the table.
 */
struct nps_gmm_cells {
  pthread_mutex_t lock;
  unsigned char *state;     /**< n_cells enum nps_gmm_cell_state */
  double *proposal_w;       /**< k scratch entries (under the lock): the proposal weights of the cell being built */
  float *squeeze;           /**< k scratch entries (under the lock): its squeezes */
  size_t built;             /**< cells built so far (under the lock) */
};

struct nps_gmm {
  size_t k;
  bool diagonal;
  double *weight;           /**< k weights as given (sum 1 within NPS_GMM_WEIGHT_SUM_TOL) */
  double *mean;             /**< k x 2 */
  double *cov;              /**< k x 4 */
  struct nps_gmm_comp *comp;
  double grid_lo_m;         /**< first cell's lower edge [m] */
  double cell_width_m;
  double inv_cell_width;    /**< [1/m] */
  size_t n_cells;
  struct nps_gmm_alias *alias; /**< n_cells x k: per cell the alias table over the upper bounds U_i */
  double *threshold;        /**< n_cells x k: F[c] of each column, exact */
  float *squeeze;           /**< n_cells x k: lower bound L_i / U_i of component i's acceptance ratio (rounded down) */
  struct nps_gmm_cells *cells;
};

static int validate(size_t k, const double *weight, const double *mean, const double *cov,
                    size_t *bad, char *err, size_t err_len)
{
  *bad = k;
  if (k == 0 || k > NPS_GMM_MAX_COMPONENTS) {
    nps_error_set(err, err_len, "a mixture needs 1 to %d components, not %zu", NPS_GMM_MAX_COMPONENTS, k);
    return -1;
  }
  double sum = 0.0;
  for (size_t i = 0; i < k; i++) {
    const double *c = cov + 4 * i;
    *bad = i;
    if (!isfinite(weight[i]) || !isfinite(mean[2 * i]) || !isfinite(mean[2 * i + 1]) ||
        !isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]) || !isfinite(c[3])) {
      nps_error_set(err, err_len, "component %zu: a weight, mean or covariance is NaN or infinite", i);
      return -1;
    }
    if (weight[i] < 0.0) {
      nps_error_set(err, err_len, "component %zu: negative weight %g", i, weight[i]);
      return -1;
    }
    if (c[0] <= 0.0 || c[3] <= 0.0) {
      nps_error_set(err, err_len, "component %zu: variances must be > 0 (var_true %g, var_measured %g)", i, c[0], c[3]);
      return -1;
    }
    if (fabs(c[1] - c[2]) > 1e-12 * sqrt(c[0] * c[3])) {
      nps_error_set(err, err_len, "component %zu: covariance matrix is not symmetric (%g vs %g)", i, c[1], c[2]);
      return -1;
    }
    if (c[1] * c[1] >= (1.0 - NPS_GMM_SINGULAR_TOL) * c[0] * c[3]) {
      nps_error_set(err, err_len, "component %zu: singular covariance (|correlation| = 1: cov %g, variances %g, %g)",
              i, c[1], c[0], c[3]);
      return -1;
    }
    sum += weight[i];
  }
  *bad = k;
  if (!(fabs(sum - 1.0) <= NPS_GMM_WEIGHT_SUM_TOL)) {
    nps_error_set(err, err_len, "weights sum to %.9g, not 1 (tolerance %g)", sum, NPS_GMM_WEIGHT_SUM_TOL);
    return -1;
  }
  return 0;
}

/** Distance from x to the interval [a, b] (0 inside). */
static inline double interval_dist(double x, double a, double b)
{
  return x < a ? a - x : (x > b ? x - b : 0.0);
}

/** log(phi_i N(t; mu_t,i, s_tt,i)). */
static inline double comp_log_weight(const struct nps_gmm_comp *c, double t_m)
{
  double d = t_m - c->mu_t;
  return c->log_norm - d * d * c->inv_2var_t;
}

/** Lower edge of cell `cell` [m] (one expression for the table build and the sampler). */
static inline double cell_lo(const struct nps_gmm *g, size_t cell)
{
  return g->grid_lo_m + (double)cell * g->cell_width_m;
}

/** Step the bits of a float by `by` (+1: the next float above f >= 0, -1: the next below f > 0): non-negative
 * IEEE-754 floats are ordered like their bit patterns (and the float below +inf is FLT_MAX). */
static inline float float_step(float f, int by)
{
  uint32_t bits;
  memcpy(&bits, &f, sizeof(bits));
  bits += (uint32_t)by;
  memcpy(&f, &bits, sizeof(f));
  return f;
}

/** x >= 0 rounded down to a float (the float below, if rounding to nearest went up: nextafterf(f, 0) without the call). */
static float float_below(double x)
{
  float f = (float)x;
  return (double)f > x ? float_step(f, -1) : f;
}

/** The next float above f >= 0. */
static inline float float_step_up(float f)
{
  return float_step(f, 1);
}

/** The acceptance ratio's lower bound L_i / U_i on [a, b], rounded down to a float. */
static float squeeze_on_cell(const struct nps_gmm_comp *c, double a, double b)
{
  /* log phi N(t) is a concave parabola in t: its maximum on [a, b] is at the point nearest mu_t,
   * its minimum at the farthest end. */
  double near = interval_dist(c->mu_t, a, b), far = fmax(fabs(a - c->mu_t), fabs(b - c->mu_t));
  return float_below(exp(-(far * far - near * near) * c->inv_2var_t));
}

/** A squeeze in [0, 1] rounded down to a multiple of 1/256 [1/256]. */
static uint8_t squeeze_256ths(float squeeze)
{
  /* floor(256 squeeze) capped at 255 (a NaN too, as fmin would): 256 squeeze is exact, truncation is floor on >= 0 */
  const float scaled = 256.0f * squeeze;
  return !(scaled < 255.0f) ? 255 : (uint8_t)scaled;
}

/**
 * The alias table of one cell: GSL's Walker table over the proposal weights U_i / max U (proposal_w, k
 * entries), copied with the squeeze of each component into the cell's row of the tables.
 */
static int fill_cell(const struct nps_gmm *g, size_t cell, const double *proposal_w, const float *squeeze)
{
  gsl_ran_discrete_t *table = gsl_ran_discrete_preproc(g->k, proposal_w);
  if (table == NULL) {
    return -1;
  }
  const size_t row = cell * g->k;
  for (size_t c = 0; c < g->k; c++) {
    g->alias[row + c] = (struct nps_gmm_alias) {
      .keep_below = float_below(table->F[c]),
      .alias = (uint16_t)table->A[c],
      .squeeze_own = squeeze_256ths(squeeze[c]),
      .squeeze_alias = squeeze_256ths(squeeze[table->A[c]]),
    };
    g->threshold[row + c] = table->F[c];
    g->squeeze[row + c] = squeeze[c];
  }
  gsl_ran_discrete_free(table);
  return 0;
}

/** The cells' extent and the tables' memory, none of it filled yet (cell_ready fills a cell on its first draw). */
static int plan_grid(struct nps_gmm *g)
{
  double lo = INFINITY, hi = -INFINITY, sd_min = INFINITY;
  for (size_t i = 0; i < g->k; i++) {
    double sd_t = sqrt(g->cov[4 * i]);
    if (g->weight[i] <= 0.0) {
      continue;
    }
    lo = fmin(lo, g->mean[2 * i] - NPS_GMM_GRID_SIGMAS * sd_t);
    hi = fmax(hi, g->mean[2 * i] + NPS_GMM_GRID_SIGMAS * sd_t);
    sd_min = fmin(sd_min, sd_t);
  }
  double cells = ceil((hi - lo) / (sd_min / NPS_GMM_CELLS_PER_SIGMA));
  g->n_cells = (size_t)fmin(fmax(cells, NPS_GMM_MIN_CELLS), NPS_GMM_MAX_CELLS);
  g->grid_lo_m = lo;
  g->cell_width_m = (hi - lo) / (double)g->n_cells;
  g->inv_cell_width = 1.0 / g->cell_width_m;
  /* left unfilled: the pages of the cells never drawn in are never touched */
  g->alias = malloc(g->n_cells * g->k * sizeof(*g->alias));
  g->threshold = malloc(g->n_cells * g->k * sizeof(*g->threshold));
  g->squeeze = malloc(g->n_cells * g->k * sizeof(*g->squeeze));
  g->cells = calloc(1, sizeof(*g->cells));
  if (!g->alias || !g->threshold || !g->squeeze || !g->cells) {
    return -1;
  }
  g->cells->state = calloc(g->n_cells, sizeof(*g->cells->state));
  g->cells->proposal_w = malloc(g->k * sizeof(*g->cells->proposal_w));
  g->cells->squeeze = malloc(g->k * sizeof(*g->cells->squeeze));
  if (!g->cells->state || !g->cells->proposal_w || !g->cells->squeeze ||
      pthread_mutex_init(&g->cells->lock, NULL) != 0) {
    free(g->cells->state);   /* nps_gmm_free destroys the lock only with the state array present */
    g->cells->state = NULL;
    return -1;
  }
  return 0;
}

/** Fill cell `cell`'s row of the tables: the proposal U_i / max U of every component on it (under the lock). */
static int build_cell(const struct nps_gmm *g, size_t cell)
{
  double *upper = g->cells->proposal_w, a = cell_lo(g, cell), b = cell_lo(g, cell + 1), max_log = -INFINITY;
  float *squeeze = g->cells->squeeze;
  for (size_t i = 0; i < g->k; i++) {
    const struct nps_gmm_comp *c = &g->comp[i];
    double near = interval_dist(c->mu_t, a, b);
    upper[i] = c->log_norm - near * near * c->inv_2var_t;   /* log U_i: the maximum on the cell */
    squeeze[i] = squeeze_on_cell(c, a, b);
    max_log = fmax(max_log, upper[i]);
  }
  for (size_t i = 0; i < g->k; i++) {
    upper[i] = exp(upper[i] - max_log);  /* now the proposal weight U_i / max U */
  }
  return fill_cell(g, cell, upper, squeeze);
}

/** Build cell `cell` unless a draw in another thread did meanwhile; whether it is built (out of memory: never). */
static __attribute__((noinline, cold)) bool build_cell_once(const struct nps_gmm *g, size_t cell)
{
  struct nps_gmm_cells *cells = g->cells;
  pthread_mutex_lock(&cells->lock);
  unsigned char state = __atomic_load_n(&cells->state[cell], __ATOMIC_RELAXED);
  if (state == NPS_GMM_CELL_UNBUILT) {
    state = build_cell(g, cell) == 0 ? NPS_GMM_CELL_BUILT : NPS_GMM_CELL_FAILED;
    cells->built += state == NPS_GMM_CELL_BUILT;
    __atomic_store_n(&cells->state[cell], state, __ATOMIC_RELEASE);
  }
  pthread_mutex_unlock(&cells->lock);
  return state == NPS_GMM_CELL_BUILT;
}

/** Whether cell `cell`'s table can be read, built on its first draw (a cell out of memory draws by the exact method). */
static inline bool cell_ready(const struct nps_gmm *g, size_t cell)
{
  const unsigned char state = __atomic_load_n(&g->cells->state[cell], __ATOMIC_ACQUIRE);
  return state == NPS_GMM_CELL_BUILT || (state == NPS_GMM_CELL_UNBUILT && build_cell_once(g, cell));
}

struct nps_gmm *nps_gmm_new(size_t k, const double *weight, const double *mean, const double *cov,
                            size_t *bad_component, char *err, size_t err_len)
{
  size_t bad_local;
  size_t *bad = bad_component ? bad_component : &bad_local;
  if (validate(k, weight, mean, cov, bad, err, err_len) != 0) {
    return NULL;
  }
  struct nps_gmm *g = calloc(1, sizeof(*g));
  if (g == NULL) {
    nps_error_set(err, err_len, "out of memory");
    return NULL;
  }
  g->k = k;
  g->weight = malloc(k * sizeof(double));
  g->mean = malloc(2 * k * sizeof(double));
  g->cov = malloc(4 * k * sizeof(double));
  g->comp = malloc(k * sizeof(*g->comp));
  if (!g->weight || !g->mean || !g->cov || !g->comp) {
    goto fail;
  }
  g->diagonal = true;
  for (size_t i = 0; i < k; i++) {
    const double *c = cov + 4 * i;
    double s_tm = 0.5 * (c[1] + c[2]);
    g->weight[i] = weight[i];  /* as given: conditional weights are normalised at each true range */
    g->mean[2 * i] = mean[2 * i];
    g->mean[2 * i + 1] = mean[2 * i + 1];
    g->cov[4 * i] = c[0];
    g->cov[4 * i + 1] = g->cov[4 * i + 2] = s_tm;
    g->cov[4 * i + 3] = c[3];
    g->diagonal = g->diagonal && s_tm == 0.0;
    g->comp[i] = (struct nps_gmm_comp) {
      .mu_t = mean[2 * i],
      .inv_2var_t = 0.5 / c[0],
      .log_norm = log(g->weight[i]) - 0.5 * log(2.0 * M_PI * c[0]),
      .mu_m = mean[2 * i + 1],
      .slope = s_tm / c[0],
      .sd = sqrt(c[3] - s_tm * s_tm / c[0]),
    };
  }
  if (plan_grid(g) != 0) {
    goto fail;
  }
  return g;
fail:
  nps_error_set(err, err_len, "out of memory");
  *bad = k;
  nps_gmm_free(g);
  return NULL;
}

void nps_gmm_free(struct nps_gmm *gmm)
{
  if (gmm == NULL) {
    return;
  }
  if (gmm->cells != NULL) {
    if (gmm->cells->state != NULL) {
      pthread_mutex_destroy(&gmm->cells->lock);
    }
    free(gmm->cells->state);
    free(gmm->cells->proposal_w);
    free(gmm->cells->squeeze);
    free(gmm->cells);
  }
  free(gmm->alias);
  free(gmm->threshold);
  free(gmm->squeeze);
  free(gmm->comp);
  free(gmm->cov);
  free(gmm->mean);
  free(gmm->weight);
  free(gmm);
}

size_t nps_gmm_size(const struct nps_gmm *gmm)
{
  return gmm->k;
}

bool nps_gmm_is_diagonal(const struct nps_gmm *gmm)
{
  return gmm->diagonal;
}

void nps_gmm_component(const struct nps_gmm *gmm, size_t i, double *weight, double mean[2], double cov[4])
{
  *weight = gmm->weight[i];
  for (int j = 0; j < 2; j++) {
    mean[j] = gmm->mean[2 * i + j];
  }
  for (int j = 0; j < 4; j++) {
    cov[j] = gmm->cov[4 * i + j];
  }
}

size_t nps_gmm_cells_built(const struct nps_gmm *gmm)
{
  pthread_mutex_lock(&gmm->cells->lock);
  const size_t built = gmm->cells->built;
  pthread_mutex_unlock(&gmm->cells->lock);
  return built;
}

void nps_gmm_grid(const struct nps_gmm *gmm, double *lo_m, double *hi_m, size_t *n_cells)
{
  *lo_m = gmm->grid_lo_m;
  *hi_m = cell_lo(gmm, gmm->n_cells);
  *n_cells = gmm->n_cells;
}

static inline double comp_cond_mean(const struct nps_gmm_comp *c, double t_m)
{
  return c->mu_m + c->slope * (t_m - c->mu_t);
}

/** log sum_i phi_i N(t; mu_t,i, s_tt,i): the normaliser of the conditional weights. */
static double log_weight_norm(const struct nps_gmm *g, double t_m)
{
  double max_log = -INFINITY, sum = 0.0;
  for (size_t i = 0; i < g->k; i++) {
    max_log = fmax(max_log, comp_log_weight(&g->comp[i], t_m));
  }
  for (size_t i = 0; i < g->k; i++) {
    sum += exp(comp_log_weight(&g->comp[i], t_m) - max_log);
  }
  return max_log + log(sum);
}

void nps_gmm_condition(const struct nps_gmm *gmm, double t_m, double *w, double *m, double *sd)
{
  double log_norm = log_weight_norm(gmm, t_m);
  for (size_t i = 0; i < gmm->k; i++) {
    const struct nps_gmm_comp *c = &gmm->comp[i];
    if (w) {
      w[i] = exp(comp_log_weight(c, t_m) - log_norm);
    }
    if (m) {
      m[i] = comp_cond_mean(c, t_m);
    }
    if (sd) {
      sd[i] = c->sd;
    }
  }
}

void nps_gmm_conditional_moments(const struct nps_gmm *gmm, double t_m, double *mean_m, double *var_m2)
{
  /* two passes, sum w (v + (m_i - mean)^2), so far from the components no cancellation eats the variance */
  double log_norm = log_weight_norm(gmm, t_m), mean = 0.0, var = 0.0;
  for (size_t i = 0; i < gmm->k; i++) {
    const struct nps_gmm_comp *c = &gmm->comp[i];
    mean += exp(comp_log_weight(c, t_m) - log_norm) * comp_cond_mean(c, t_m);
  }
  for (size_t i = 0; i < gmm->k; i++) {
    const struct nps_gmm_comp *c = &gmm->comp[i];
    double d = comp_cond_mean(c, t_m) - mean;
    var += exp(comp_log_weight(c, t_m) - log_norm) * (c->sd * c->sd + d * d);
  }
  *mean_m = mean;
  *var_m2 = var;
}

double nps_gmm_conditional_logpdf(const struct nps_gmm *gmm, double t_m, double meas_m)
{
  /* log p(m|t) = logsumexp_i(log phi_i N(t) + log N(m; m_i(t), v_i)) - logsumexp_i(log phi_i N(t)) */
  double max_log = -INFINITY, sum = 0.0;
  for (size_t i = 0; i < gmm->k; i++) {
    const struct nps_gmm_comp *c = &gmm->comp[i];
    double z = (meas_m - comp_cond_mean(c, t_m)) / c->sd;
    double l = comp_log_weight(c, t_m) - 0.5 * z * z - log(c->sd) - 0.5 * log(2.0 * M_PI);
    if (l > max_log) {
      sum = sum * exp(max_log - l) + 1.0;
      max_log = l;
    } else {
      sum += exp(l - max_log);
    }
  }
  return max_log + log(sum) - log_weight_norm(gmm, t_m);
}

double nps_gmm_conditional_cdf(const struct nps_gmm *gmm, double t_m, double meas_m)
{
  double log_norm = log_weight_norm(gmm, t_m), p = 0.0;
  for (size_t i = 0; i < gmm->k; i++) {
    const struct nps_gmm_comp *c = &gmm->comp[i];
    p += exp(comp_log_weight(c, t_m) - log_norm) * gsl_cdf_gaussian_P(meas_m - comp_cond_mean(c, t_m), c->sd);
  }
  return fmin(p, 1.0);
}

void nps_gmm_conditional_n(const struct nps_gmm *gmm, size_t n, const double *t_m, const double *meas_m,
                           double *mean_m, double *var_m2, double *logpdf, double *cdf)
{
  for (size_t i = 0; i < n; i++) {
    if (mean_m != NULL || var_m2 != NULL) {
      double mean, var;
      nps_gmm_conditional_moments(gmm, t_m[i], &mean, &var);
      if (mean_m != NULL) {
        mean_m[i] = mean;
      }
      if (var_m2 != NULL) {
        var_m2[i] = var;
      }
    }
    if (logpdf != NULL) {
      logpdf[i] = nps_gmm_conditional_logpdf(gmm, t_m[i], meas_m[i]);
    }
    if (cdf != NULL) {
      cdf[i] = nps_gmm_conditional_cdf(gmm, t_m[i], meas_m[i]);
    }
  }
}

static inline double comp_draw(const struct nps_gmm_comp *c, double t_m, gsl_rng *r)
{
  return comp_cond_mean(c, t_m) + gsl_ran_gaussian_ziggurat(r, c->sd);
}

double nps_gmm_sample_exact(const struct nps_gmm *gmm, double t_m, gsl_rng *r)
{
  if (!isfinite(t_m)) {
    return NAN;
  }
  double max_log = -INFINITY, sum = 0.0;
  double w[NPS_GMM_MAX_COMPONENTS];   /* weights relative to the largest, each exp computed once */
  for (size_t i = 0; i < gmm->k; i++) {
    w[i] = comp_log_weight(&gmm->comp[i], t_m);
    max_log = fmax(max_log, w[i]);
  }
  for (size_t i = 0; i < gmm->k; i++) {
    w[i] = exp(w[i] - max_log);
    sum += w[i];
  }
  /* inverse CDF over the components: the first i whose cumulative weight exceeds u */
  double u = gsl_rng_uniform(r) * sum, acc = 0.0;
  size_t pick = 0;
  for (size_t i = 0; i < gmm->k; i++) {
    if (w[i] > 0.0) {
      pick = i;
      acc += w[i];
      if (u < acc) {
        break;
      }
    }
  }
  return comp_draw(&gmm->comp[pick], t_m, r);
}

/**
 * The component that uniform u proposes from a cell's row, as gsl_ran_discrete() picks it: column c = floor(u K)
 * keeps c when u < F[c], else gives A[c]. *squeeze_256ths receives the proposed component's rounded squeeze.
 */
static inline size_t propose(const struct nps_gmm *g, size_t row, double u, unsigned *squeeze_256ths)
{
  const size_t c = (size_t)(u * (double)g->k);
  const struct nps_gmm_alias *e = &g->alias[row + c];
  /* the float bound decides unless u lies within one float step above it */
  const bool keep = u < e->keep_below || (u < float_step_up(e->keep_below) && u < g->threshold[row + c]);
  *squeeze_256ths = keep ? e->squeeze_own : e->squeeze_alias;
  return keep ? c : e->alias;
}

double nps_gmm_sample(const struct nps_gmm *gmm, double t_m, gsl_rng *r)
{
  double pos = (t_m - gmm->grid_lo_m) * gmm->inv_cell_width;
  if (!(pos >= 0.0 && pos < (double)gmm->n_cells) || !cell_ready(gmm, (size_t)pos)) {
    return nps_gmm_sample_exact(gmm, t_m, r);
  }
  size_t cell = (size_t)pos, row = cell * gmm->k;
  double a = cell_lo(gmm, cell), b = cell_lo(gmm, cell + 1);
  for (int proposals = 0; proposals < NPS_GMM_MAX_PROPOSALS; proposals++) {
    unsigned squeeze_256ths;
    size_t i = propose(gmm, row, gsl_rng_uniform(r), &squeeze_256ths);
    double v = gsl_rng_uniform(r);
    const struct nps_gmm_comp *c = &gmm->comp[i];
    if (v < squeeze_256ths / 256.0) {
      return comp_draw(c, t_m, r);
    }
    /* accept when v is below the squeeze or below the ratio phi_i N(t) / U_i = exp(-((t - mu)^2 - near^2) / (2 s_tt));
     * the squeeze can only exceed the ratio for a t that rounding put into the cell from just outside it */
    double near = interval_dist(c->mu_t, a, b), d = t_m - c->mu_t;
    if (v < exp(-(d * d - near * near) * c->inv_2var_t) || v < gmm->squeeze[row + i]) {
      return comp_draw(c, t_m, r);
    }
  }
  return nps_gmm_sample_exact(gmm, t_m, r);
}
