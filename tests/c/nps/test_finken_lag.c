/*
 * The FINken flight model: exact first-order responses (x(t) = x_cmd (1 - exp(-t / tau))),
 * speed limiting, altitude hold, heading wrap, contacts; the cached terms change no bit of a step. Deterministic:
 * tolerances are rounding only.
 */
#include "test_helpers.h"
#include "nps_finken_lag.h"

#include <gsl/gsl_rng.h>
#include <stdbool.h>
#include <string.h>

static const struct nps_finken_lag_params params = {
  .velocity_tau_s = 0.5, .yaw_tau_s = 0.3, .altitude_m = 0.6, .altitude_tau_s = 0.5, .max_speed_mps = 1.0,
};

static void velocity_follows_first_order_law(void **state)
{
  (void)state;
  struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.6} };
  const double dt = 0.01;
  for (int i = 0; i < 50; i++) {   /* t = tau = 0.5 s */
    nps_finken_lag_step(&s, &params, 0.8, 0.0, 0.0, dt);
  }
  assert_close(s.vel_mps[0], 0.8 * (1.0 - exp(-1.0)), 1e-12);
  assert_close(s.vel_mps[1], 0.0, 0.0);
}

static void the_result_does_not_depend_on_the_step(void **state)
{
  (void)state;
  struct nps_finken_lag_state fine = { .pos_m = {0, 0, 0.6} }, coarse = fine;
  for (int i = 0; i < 100; i++) {
    nps_finken_lag_step(&fine, &params, 0.5, -0.5, 1.0, 0.001);
  }
  nps_finken_lag_step(&coarse, &params, 0.5, -0.5, 1.0, 0.1);
  assert_close(coarse.vel_mps[0], fine.vel_mps[0], 1e-12);
  assert_close(coarse.yaw_rad, fine.yaw_rad, 1e-12);
}

static void speed_command_is_limited(void **state)
{
  (void)state;
  struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.6} };
  for (int i = 0; i < 2000; i++) {
    nps_finken_lag_step(&s, &params, 3.0, 4.0, 0.0, 0.01);
  }
  assert_close(hypot(s.vel_mps[0], s.vel_mps[1]), params.max_speed_mps, 1e-9);
  assert_close(s.vel_mps[1] / s.vel_mps[0], 4.0 / 3.0, 1e-9);  /* direction kept */
}

static void altitude_settles_at_the_held_height(void **state)
{
  (void)state;
  struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.0} };
  for (int i = 0; i < 1000; i++) {
    nps_finken_lag_step(&s, &params, 0.0, 0.0, 0.0, 0.01);
  }
  assert_close(s.pos_m[2], 0.6, 1e-6);
}

static void heading_takes_the_short_way_round(void **state)
{
  (void)state;
  struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.6}, .yaw_rad = 3.0 };
  nps_finken_lag_step(&s, &params, 0.0, 0.0, -3.0, 0.01);
  assert_true(s.yaw_rate_rps > 0.0);   /* from 3.0 to -3.0 rad is +0.28 rad through pi */
}

/** The step as the model defines it, every term recomputed (reference for the memo and the precomputed gains). */
static void reference_step(struct nps_finken_lag_state *s, double vx, double vy, double yaw_cmd, double dt)
{
  const double speed = sqrt(vx * vx + vy * vy);
  if (speed > params.max_speed_mps && speed > 0.0) {
    vx *= params.max_speed_mps / speed;
    vy *= params.max_speed_mps / speed;
  }
  const double gv = 1.0 - exp(-dt / params.velocity_tau_s), gz = 1.0 - exp(-dt / params.altitude_tau_s);
  const double gy = 1.0 - exp(-dt / params.yaw_tau_s);
  s->vel_mps[0] += (vx - s->vel_mps[0]) * gv;
  s->vel_mps[1] += (vy - s->vel_mps[1]) * gv;
  const double z_before = s->pos_m[2];
  s->pos_m[2] += (params.altitude_m - s->pos_m[2]) * gz;
  s->vel_mps[2] = (s->pos_m[2] - z_before) * (1.0 / dt);   /* rates: a step's change times the step rate */
  s->pos_m[0] += s->vel_mps[0] * dt;
  s->pos_m[1] += s->vel_mps[1] * dt;
  const double step = remainder(yaw_cmd - s->yaw_rad, 2.0 * M_PI) * gy;
  s->yaw_rad = remainder(s->yaw_rad + step, 2.0 * M_PI);
  s->yaw_rate_rps = step * (1.0 / dt);
}

static bool same_double(double a, double b)
{
  return memcmp(&a, &b, sizeof(a)) == 0;
}

static void cached_terms_give_the_recomputed_step_bit_for_bit(void **state)
{
  (void)state;
  /* 20000 steps of commands held for 1 to 8 steps (fixed seed), headings held, across +-pi, and signed zeros:
   * the memo (speed limit) and the precomputed gains must not change a single bit */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.6} }, ref = s;
  struct nps_finken_lag_gains g;
  nps_finken_lag_gains_init(&g, &params, 0.01);
  double vx = 0.0, vy = -0.0, yaw = -0.0;
  int hold = 0;
  for (int k = 0; k < 20000; k++) {
    if (hold-- == 0) {
      hold = (int)gsl_rng_uniform_int(rng, 8);
      const unsigned kind = (unsigned)gsl_rng_uniform_int(rng, 4);
      vx = kind == 0 ? -0.0 : (kind == 3 ? vx : 3.0 * (gsl_rng_uniform(rng) - 0.5));
      vy = kind == 0 ? 0.0 : 3.0 * (gsl_rng_uniform(rng) - 0.5);
      yaw = kind == 1 ? ref.yaw_rad : (kind == 2 ? M_PI * (1.0 - 1e-9 * gsl_rng_uniform(rng)) : 7.0 * (gsl_rng_uniform(rng) - 0.5));
    }
    nps_finken_lag_advance(&s, &params, &g, vx, vy, yaw);
    reference_step(&ref, vx, vy, yaw, 0.01);
    for (int i = 0; i < 3; i++) {
      assert_true(same_double(s.pos_m[i], ref.pos_m[i]) && same_double(s.vel_mps[i], ref.vel_mps[i]));
    }
    assert_true(same_double(s.yaw_rad, ref.yaw_rad) && same_double(s.yaw_rate_rps, ref.yaw_rate_rps));
    assert_true(fabs(s.yaw_rad) <= M_PI);   /* wrapped, also after commands beyond +-pi */
  }
  gsl_rng_free(rng);
}

static void heading_wrap_is_the_ieee_remainder_bit_for_bit(void **state)
{
  (void)state;
  /* with no heading lag (gain 1) a step turns to wrap(cmd - yaw) and wraps the sum: both must be remainder(., 2 pi)
   * bit for bit, at the borders of its shortcuts (|a| = pi, 2 pi, 3 pi, 4 pi and their neighbours, both signs:
   * at -2 pi remainder gives -0) and for 20000 random commands within +-5 pi (fixed seed), beyond the shortcuts too */
  struct nps_finken_lag_params instant = params;
  instant.yaw_tau_s = 0.0;
  struct nps_finken_lag_gains g;
  nps_finken_lag_gains_init(&g, &instant, 0.01);
  assert_true(g.yaw == 1.0);
  const double two_pi = 2.0 * M_PI;
  const double borders[] = { M_PI, nextafter(M_PI, 0.0), nextafter(M_PI, 4.0), two_pi, nextafter(two_pi, 0.0),
                             nextafter(two_pi, 7.0), 3.0 * M_PI, nextafter(3.0 * M_PI, 0.0), nextafter(3.0 * M_PI, 10.0),
                             2.0 * two_pi, nextafter(2.0 * two_pi, 13.0) };
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  for (int k = 0; k < 20000 + 22; k++) {
    const double yaw0 = k < 22 ? 0.0 : M_PI * (2.0 * gsl_rng_uniform(rng) - 1.0);
    const double cmd = k < 22 ? (k % 2 ? -1.0 : 1.0) * borders[k / 2] : 5.0 * M_PI * (2.0 * gsl_rng_uniform(rng) - 1.0);
    struct nps_finken_lag_state s = { .pos_m = {0, 0, 0.6}, .yaw_rad = yaw0 };
    nps_finken_lag_advance(&s, &instant, &g, 0.0, 0.0, cmd);
    const double step = remainder(cmd - yaw0, two_pi);
    assert_true(same_double(s.yaw_rad, remainder(yaw0 + step, two_pi)));
    assert_true(same_double(s.yaw_rate_rps, step * (1.0 / 0.01)));
  }
  gsl_rng_free(rng);
}

static void a_contact_stops_the_motion_into_the_push_only(void **state)
{
  (void)state;
  /* 1000 random velocities and pushes (1e-9 m to 0.2 m, any direction): the position is the corrected one; a
   * velocity into the push loses exactly its part along the push (the result is orthogonal to the push, and the
   * part across is kept), to rounding; one away from the push or across it is kept bit for bit */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  int stopped = 0;
  for (int i = 0; i < 1000; i++) {
    struct nps_finken_lag_state s = {
      .pos_m = { 3.0 * gsl_rng_uniform(rng), 4.0 * gsl_rng_uniform(rng), 0.6 },
      .vel_mps = { 2.0 * gsl_rng_uniform(rng) - 1.0, 2.0 * gsl_rng_uniform(rng) - 1.0, 0.01 },
    };
    const double push_len = pow(10.0, -9.0 + 8.3 * gsl_rng_uniform(rng)), angle = 2.0 * M_PI * gsl_rng_uniform(rng);
    const double u[2] = { cos(angle), sin(angle) };
    const double to[2] = { s.pos_m[0] + push_len * u[0], s.pos_m[1] + push_len * u[1] };
    const struct nps_finken_lag_state before = s;
    const double across = before.vel_mps[0] * u[1] - before.vel_mps[1] * u[0];
    nps_finken_lag_take_contact(&s, to);
    assert_true(s.pos_m[0] == to[0] && s.pos_m[1] == to[1] && s.pos_m[2] == before.pos_m[2]);
    assert_true(s.vel_mps[2] == before.vel_mps[2]);
    const double push[2] = { to[0] - before.pos_m[0], to[1] - before.pos_m[1] };
    if (before.vel_mps[0] * push[0] + before.vel_mps[1] * push[1] >= 0.0) {
      assert_memory_equal(s.vel_mps, before.vel_mps, sizeof(s.vel_mps));
      continue;
    }
    stopped++;
    /* the rounded push's direction differs from u by ~1e-16 / push_len: a tolerance in proportion */
    const double tol = 1e-15 + 4e-16 / push_len;
    assert_close(s.vel_mps[0] * u[0] + s.vel_mps[1] * u[1], 0.0, tol);
    assert_close(s.vel_mps[0] * u[1] - s.vel_mps[1] * u[0], across, tol);
  }
  assert_true(stopped > 400);   /* about half of the velocities go into the push */
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(velocity_follows_first_order_law),
    cmocka_unit_test(the_result_does_not_depend_on_the_step),
    cmocka_unit_test(speed_command_is_limited),
    cmocka_unit_test(altitude_settles_at_the_held_height),
    cmocka_unit_test(heading_takes_the_short_way_round),
    cmocka_unit_test(heading_wrap_is_the_ieee_remainder_bit_for_bit),
    cmocka_unit_test(cached_terms_give_the_recomputed_step_bit_for_bit),
    cmocka_unit_test(a_contact_stops_the_motion_into_the_push_only),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
