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
 * @file nps_gmm.h
 * Conditional Gaussian mixture: a joint mixture over (true range t, measured range m), conditioned on t.
 *
 * Joint: p(t, m) = sum_i phi_i N([t, m]; mu_i, S_i), S_i = [[s_tt, s_tm], [s_tm, s_mm]] (full or diagonal).
 * Conditioned on t (Bishop, PRML 2006, eqs. 2.81-2.82 and 9.7):
 *   w_i(t)  = phi_i N(t; mu_t,i, s_tt,i) / sum_j phi_j N(t; mu_t,j, s_tt,j)   (computed in log space)
 *   m_i(t)  = mu_m,i + s_tm,i / s_tt,i * (t - mu_t,i)
 *   v_i     = s_mm,i - s_tm,i^2 / s_tt,i
 *   p(m | t) = sum_i w_i(t) N(m; m_i(t), v_i)
 * Sampling picks ONE component i with probability w_i(t), then draws N(m_i(t), v_i).
 *
 * Fast path: the true-range axis is cut into cells; each cell holds a Walker alias table
 * (gsl_ran_discrete_preproc) over an upper bound U_i of phi_i N(t; mu_t,i, s_tt,i) on the cell, built on the first
 * draw in that cell (safely when several threads draw: nps_gmm.c, struct nps_gmm_cells). A proposed
 * component is accepted with probability phi_i N(t; ...) / U_i (a precomputed lower bound accepts most
 * proposals without an exp()), which makes the draw exact (rejection sampling from a discrete law),
 * O(1) on average, without allocation once the cell is built. Outside the grid, and after 64 rejected proposals
 * in a row (cells far too wide for their bounds: a component 1e36 m wide), the exact O(K) method is used.
 * The tables are kept in 8 bytes per component and cell (values rounded down, the exact ones consulted only
 * where the rounding could matter), so that they stay in cache: the proposal is the one gsl_ran_discrete()
 * makes with the same uniform, and every draw is the same as with GSL's own tables.
 */

#ifndef NPS_GMM_H
#define NPS_GMM_H

#include <stddef.h>
#include <stdbool.h>
#include <gsl/gsl_rng.h>

/** Largest number of components a mixture may have. */
#define NPS_GMM_MAX_COMPONENTS 4096
/** Tolerance on |sum of weights - 1| at load (conditional weights are normalised at each true range). */
#define NPS_GMM_WEIGHT_SUM_TOL 1e-6

struct nps_gmm;

/**
 * Build a mixture (its cells' sampling tables are built later, each on its first draw).
 * @param k       number of components (1 .. NPS_GMM_MAX_COMPONENTS)
 * @param weight  k mixture weights phi_i (>= 0, summing to 1 within NPS_GMM_WEIGHT_SUM_TOL)
 * @param mean    k x 2 means, row i = (mu_t,i [m], mu_m,i [m])
 * @param cov     k x 2 x 2 covariances [m^2], row-major, symmetric, positive definite
 * @param bad_component  set to the index of the offending component on error (k when not one component)
 * @param err     receives the reason on error (may be NULL)
 * @return the mixture, or NULL on error (nothing allocated then)
 */
struct nps_gmm *nps_gmm_new(size_t k, const double *weight, const double *mean, const double *cov,
                            size_t *bad_component, char *err, size_t err_len);
void nps_gmm_free(struct nps_gmm *gmm);

/** Number of components. */
size_t nps_gmm_size(const struct nps_gmm *gmm);
/** True when every covariance is diagonal. */
bool nps_gmm_is_diagonal(const struct nps_gmm *gmm);
/** Component i as given: weight, mean[2], cov[4] (row-major). */
void nps_gmm_component(const struct nps_gmm *gmm, size_t i, double *weight, double mean[2], double cov[4]);

/**
 * The conditional mixture at true range t_m: normalised weights w[i], means m[i] [m], standard deviations
 * sd[i] [m] (arrays of nps_gmm_size() entries, any may be NULL).
 */
void nps_gmm_condition(const struct nps_gmm *gmm, double t_m, double *w, double *m, double *sd);

/** Mean and variance of p(m | t) (law of total variance: sum w (v + (m_i - mean)^2)). */
void nps_gmm_conditional_moments(const struct nps_gmm *gmm, double t_m, double *mean_m, double *var_m2);
/** log p(m | t) [log 1/m]; finite for every finite t and m. */
double nps_gmm_conditional_logpdf(const struct nps_gmm *gmm, double t_m, double meas_m);
/** P(measured <= m | t). */
double nps_gmm_conditional_cdf(const struct nps_gmm *gmm, double t_m, double meas_m);

/** The three functions above for n (t, m) pairs (bindings; any output may be NULL). */
void nps_gmm_conditional_n(const struct nps_gmm *gmm, size_t n, const double *t_m, const double *meas_m,
                           double *mean_m, double *var_m2, double *logpdf, double *cdf);

/** One draw of the measured range given the true range t_m [m]: O(1) on the grid (see file comment). */
double nps_gmm_sample(const struct nps_gmm *gmm, double t_m, gsl_rng *r);
/** The same law by the exact O(K) method (log-sum-exp weights, inverse CDF over components). */
double nps_gmm_sample_exact(const struct nps_gmm *gmm, double t_m, gsl_rng *r);

/** How many of the grid's cells have their alias table built (each on its first draw). */
size_t nps_gmm_cells_built(const struct nps_gmm *gmm);

/** The true-range interval [m] covered by the alias-table grid and its number of cells. */
void nps_gmm_grid(const struct nps_gmm *gmm, double *lo_m, double *hi_m, size_t *n_cells);

#endif /* NPS_GMM_H */
