/*
 * Drift of a copter's position estimate (nps_ins_drift.h): the velocity error's variance and correlation, the
 * position error's variance against the integrated Gauss-Markov law, reproducibility per (seed, vehicle), and
 * sd 0 as no drift.
 *
 * Conventions in test_effect_stats.h. Specific to this file:
 *   - VEHICLES = 2000 independent streams (vehicles 1..2000 under SEED), both horizontal axes: n = 4000 samples
 *     per quantity, each taken once per stream at a fixed time (no sample used twice);
 *   - dt = 0.01 s (the host's step), sd = 0.02 m/s, tau = 10 s, T = 30 s;
 *   - every check within K_SIGMA = 5 standard errors of its estimator (formula at each check): two-sided false
 *     failure 5.7e-7 per check, 4 checks, about 2.3e-6 per run (for another seed; this one is fixed);
 *   - each check is paired with a wrong model (tau 5 or 20 s, sd 15 % low or high) that must fall outside the
 *     same tolerance around the measured value.
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <stdlib.h>
#include <string.h>

#include "nps_ins_drift.h"

#define SEED 31u
#define VEHICLES 2000
#define DT_S 0.01
#define SD_MPS 0.02
#define TAU_S 10.0
#define STEPS 3000            /* T = STEPS * DT_S = 30 s */
#define LAG_STEPS 100         /* the velocity error's correlation is measured over 1 s */

/*
 * The position error's variance after N = T / dt steps.
 *
 * Continuous time: v is a stationary Gauss-Markov (Ornstein-Uhlenbeck) process, E v = 0,
 * E v(t) v(u) = sd^2 exp(-|t - u| / tau) (v starts from its stationary law N(0, sd^2)), e(T) = int_0^T v dt, so
 *   Var e(T) = int_0^T int_0^T sd^2 exp(-|t - u| / tau) du dt = 2 sd^2 int_0^T (T - r) exp(-r / tau) dr
 *            = 2 sd^2 tau^2 (T / tau - 1 + exp(-T / tau)),
 * which tends to the random walk 2 sd^2 tau T for T >> tau (nps_ins_drift.h's diffusion).
 *
 * What the code computes: e_N = dt sum_{i=0}^{N-1} v_i (a step adds the velocity error from before its update),
 * v_i the exact discretisation, a stationary AR(1) with a = exp(-dt / tau), Cov(v_i, v_j) = sd^2 a^|i-j|:
 *   Var e_N = dt^2 sd^2 (N + 2 sum_{k=1}^{N-1} (N - k) a^k)
 *           = dt^2 sd^2 (N (1 + a) / (1 - a) - 2 a (1 - a^N) / (1 - a)^2).
 * (1 + a) / (1 - a) = coth(dt / (2 tau)) = 2 tau / dt + dt / (6 tau) + ..., so the Euler sum differs from the
 * integral by a relative O((dt / tau)^2) in the diffusion plus O(dt / T) end terms: at dt = 0.01 s, tau = 10 s,
 * T = 30 s, by less than 1e-5 (asserted below), far inside the tolerance. The test compares with the sum.
 */
static double var_pos_continuous(double sd, double tau, double t)
{
  return 2.0 * sd * sd * tau * tau * (t / tau - 1.0 + exp(-t / tau));
}

static double var_pos_euler(double sd, double tau, double dt, unsigned n)
{
  const double a = exp(-dt / tau);
  return dt * dt * sd * sd * (n * (1.0 + a) / (1.0 - a) - 2.0 * a * (1.0 - pow(a, n)) / ((1.0 - a) * (1.0 - a)));
}

/** Sample correlation of the pairs (x[i], y[i]). */
static double correlation(const double *x, const double *y, size_t n)
{
  const double mx = stats_mean(x, n), my = stats_mean(y, n);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (size_t i = 0; i < n; i++) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxy / sqrt(sxx * syy);
}

/** Assert a wrong model's value lies outside tol of the measured value (the check can tell it from the truth). */
#define assert_rejects(measured, wrong, tol) do { \
    double m_ = (measured), w_ = (wrong), t_ = (tol); \
    if (!(fabs(m_ - w_) > t_)) { \
      print_error("%s = %.9g is within %.3g of the wrong model's %s = %.9g\n", #measured, m_, t_, #wrong, w_); \
      fail(); \
    } \
  } while (0)

static const struct nps_ins_drift_params params = { .sd_mps = SD_MPS, .tau_s = TAU_S };

static void start(struct nps_ins_drift *d, const struct nps_ins_drift_params *p, uint64_t seed, uint64_t vehicle)
{
  assert_int_equal(nps_ins_drift_init(d, p, seed, vehicle), 0);
}

static void the_drift_follows_the_integrated_gauss_markov_law(void **state)
{
  (void)state;
  const size_t n = 2 * VEHICLES;
  double *pos = malloc(n * sizeof(double)), *vel = malloc(n * sizeof(double)), *vel_lag = malloc(n * sizeof(double));
  assert_non_null(pos);
  assert_non_null(vel);
  assert_non_null(vel_lag);
  for (unsigned v = 0; v < VEHICLES; v++) {
    struct nps_ins_drift d;
    start(&d, &params, SEED, v + 1);
    for (unsigned k = 1; k <= STEPS; k++) {
      nps_ins_drift_step(&d, &params, DT_S);
      if (k == STEPS - LAG_STEPS) {
        memcpy(&vel_lag[2 * v], d.vel_error_mps, 2 * sizeof(double));
      }
    }
    memcpy(&pos[2 * v], d.pos_error_m, 2 * sizeof(double));
    memcpy(&vel[2 * v], d.vel_error_mps, 2 * sizeof(double));
    assert_true(d.pos_error_m[2] == 0.0);   /* up stays 0 */
    nps_ins_drift_free(&d);
  }
  const double t_s = STEPS * DT_S, lag_s = LAG_STEPS * DT_S;

  /* the Euler sum and the integral agree far inside the tolerance */
  const double var_e = var_pos_euler(SD_MPS, TAU_S, DT_S, STEPS);
  print_message("# Var e(T): Euler sum %.9g m^2, integral %.9g m^2 (relative %.3g)\n", var_e,
                var_pos_continuous(SD_MPS, TAU_S, t_s), var_e / var_pos_continuous(SD_MPS, TAU_S, t_s) - 1.0);
  assert_close(var_e / var_pos_continuous(SD_MPS, TAU_S, t_s), 1.0, 1e-5);

  /* position error, normal with mean 0: the mean within K sigma / sqrt(n); the unbiased sample variance s^2 of a
   * normal has Var s^2 = 2 sigma^4 / (n - 1), so within K sigma^2 sqrt(2 / (n - 1)) (11 % at n = 4000) */
  const double mean_e = stats_mean(pos, n), s2_e = stats_var(pos, n);
  const double tol_var_e = K_SIGMA * var_e * sqrt(2.0 / (double)(n - 1));
  print_message("# Var e(T) measured %.9g m^2, theory %.9g m^2 +- %.3g (n = %zu)\n", s2_e, var_e, tol_var_e, n);
  assert_close(mean_e, 0.0, K_SIGMA * sqrt(var_e / (double)n));
  assert_close(s2_e, var_e, tol_var_e);
  /* the wrong models: tau 5 s (variance x 0.61) or 20 s (x 1.41); sd 15 % low or high (x 0.72, x 1.32) */
  assert_rejects(s2_e, var_pos_euler(SD_MPS, 5.0, DT_S, STEPS), tol_var_e);
  assert_rejects(s2_e, var_pos_euler(SD_MPS, 20.0, DT_S, STEPS), tol_var_e);
  assert_rejects(s2_e, var_pos_euler(0.85 * SD_MPS, TAU_S, DT_S, STEPS), tol_var_e);
  assert_rejects(s2_e, var_pos_euler(1.15 * SD_MPS, TAU_S, DT_S, STEPS), tol_var_e);

  /* velocity error: stationary, Var v = sd^2 at every step, same estimator and tolerance */
  const double var_v = SD_MPS * SD_MPS, s2_v = stats_var(vel, n), tol_var_v = K_SIGMA * var_v * sqrt(2.0 / (n - 1.0));
  print_message("# Var v(T) measured %.9g (m/s)^2, theory %.9g +- %.3g\n", s2_v, var_v, tol_var_v);
  assert_close(s2_v, var_v, tol_var_v);
  assert_rejects(s2_v, 0.85 * 0.85 * var_v, tol_var_v);
  assert_rejects(s2_v, 1.15 * 1.15 * var_v, tol_var_v);

  /* its correlation over 1 s is exp(-1 / tau): Fisher's z = atanh(r) of a bivariate normal's sample correlation
   * is close to normal with sd 1 / sqrt(n - 3), so |atanh(r) - atanh(rho)| <= K / sqrt(n - 3) (0.079 here);
   * tau 5 s (rho 0.819) is 0.35 away in z, tau 8 s (rho 0.882) and 12.5 s (rho 0.923) 0.11 */
  const double r = correlation(vel_lag, vel, n), rho = exp(-lag_s / TAU_S), tol_z = K_SIGMA / sqrt(n - 3.0);
  print_message("# corr v(T - 1 s), v(T) measured %.9g, theory %.9g (Fisher z +- %.3g)\n", r, rho, tol_z);
  assert_close(atanh(r), atanh(rho), tol_z);
  assert_rejects(atanh(r), atanh(exp(-lag_s / 5.0)), tol_z);
  assert_rejects(atanh(r), atanh(exp(-lag_s / 8.0)), tol_z);
  assert_rejects(atanh(r), atanh(exp(-lag_s / 12.5)), tol_z);

  free(pos);
  free(vel);
  free(vel_lag);
}

/** The first `steps` (velocity, position) errors of stream (seed, vehicle), 4 doubles a step. */
static double *sequence(uint64_t seed, uint64_t vehicle, unsigned steps)
{
  double *x = malloc(4 * steps * sizeof(double));
  assert_non_null(x);
  struct nps_ins_drift d;
  start(&d, &params, seed, vehicle);
  for (unsigned k = 0; k < steps; k++) {
    nps_ins_drift_step(&d, &params, DT_S);
    memcpy(&x[4 * k], d.vel_error_mps, 2 * sizeof(double));
    memcpy(&x[4 * k + 2], d.pos_error_m, 2 * sizeof(double));
  }
  nps_ins_drift_free(&d);
  assert_null(d.rng);
  return x;
}

static void a_seed_and_vehicle_give_the_same_drift_and_others_differ(void **state)
{
  (void)state;
  const unsigned steps = 1000;
  double *a = sequence(SEED, 3, steps), *same = sequence(SEED, 3, steps);
  double *other_vehicle = sequence(SEED, 4, steps), *other_seed = sequence(SEED + 1, 3, steps);
  assert_memory_equal(a, same, 4 * steps * sizeof(double));   /* bit-identical */
  /* other streams: no value in common (continuous draws; a shared one would mean a shared stream) */
  for (unsigned i = 0; i < 4 * steps; i++) {
    assert_true(a[i] != other_vehicle[i]);
    assert_true(a[i] != other_seed[i]);
  }
  free(a);
  free(same);
  free(other_vehicle);
  free(other_seed);
}

static void sd_0_is_no_drift(void **state)
{
  (void)state;
  const struct nps_ins_drift_params none = { .sd_mps = 0.0, .tau_s = TAU_S };
  struct nps_ins_drift d;
  start(&d, &none, SEED, 1);
  for (unsigned k = 0; k < STEPS; k++) {
    nps_ins_drift_step(&d, &none, DT_S);
    for (int axis = 0; axis < 3; axis++) {
      assert_true(d.pos_error_m[axis] == 0.0);
    }
    assert_true(d.vel_error_mps[0] == 0.0 && d.vel_error_mps[1] == 0.0);
  }
  nps_ins_drift_free(&d);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_drift_follows_the_integrated_gauss_markov_law),
    cmocka_unit_test(a_seed_and_vehicle_give_the_same_drift_and_others_differ),
    cmocka_unit_test(sd_0_is_no_drift),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
