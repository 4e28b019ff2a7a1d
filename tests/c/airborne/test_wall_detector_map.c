/*
 * The wall map (wall_detector_map.h) with the module's default parameters: where a beam meets a line and with what
 * variance (hand-computed), what the map says about a reading (hand-computed g), what it learns and from which
 * echoes, how it tells a wall from a body that stays still, when it forgets, and the Kalman filter of a line
 * against a brute-force search of the same posterior. Poses: x east, y north; bearings clockwise from north.
 */
#include "test_helpers.h"
#include "wall_detector_fixtures.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <string.h>

static struct wall_detector_params defaults;
static struct wall_detector_model_terms terms;
static struct wall_detector_map map;

/** g_map: the log of the map's ratio (wall_detector_map_ratio). */
static double map_llr(const struct wall_detector_map_prediction *prediction, float range_m)
{
  return log(wall_detector_map_ratio(&terms, &defaults.map, prediction, range_m));
}

static int setup(void **state)
{
  (void)state;
  defaults = wall_detector_default_params();
  wall_detector_model_terms_init(&terms, &defaults.model);
  memset(&map, 0, sizeof(map));
  return 0;
}

static struct wall_detector_map_beam beam(float x_m, float y_m, float bearing_deg)
{
  const struct wall_detector_pose pose = { x_m, y_m, 0.f };
  return wall_detector_map_beam_of(&pose, bearing_deg * (float)(M_PI / 180.0));
}

/** A line through (x, y) with its normal at bearing theta, seen from s_min to s_max along it. */
static void put_line(int i, float x_m, float y_m, float theta_deg, float s_min_m, float s_max_m)
{
  const float theta_rad = theta_deg * (float)(M_PI / 180.0);
  map.line[i] = (struct wall_detector_map_line) {
    .used = true, .c_x_m = x_m, .c_y_m = y_m, .theta_rad = theta_rad, .n_x = sinf(theta_rad), .n_y = cosf(theta_rad),
    .p_dd_m2 = 0.0004f, .p_dt_m = 0.f, .p_tt_rad2 = 0.0001f, .s_min_m = s_min_m, .s_max_m = s_max_m,
    .stamp_us = 1000000u, .echoes = 100,
  };
}

/** The map's prediction at 1 s (no drift since the lines' stamps). */
static struct wall_detector_map_prediction predict(const struct wall_detector_map_beam *b)
{
  return wall_detector_map_predict(&map, &defaults.map, &defaults.model, b, 1000000u);
}

static void a_beam_meets_the_nearest_line_within_its_reach(void **state)
{
  (void)state;
  /* the north wall y = 3 (normal bearing 0) seen from x = -1 to 1, the east wall x = 2 (normal bearing 90 deg) */
  put_line(0, 0.f, 3.f, 0.f, -1.f, 1.f);
  put_line(1, 2.f, 0.f, 90.f, -1.f, 1.f);
  const float sigma2 = defaults.model.track_sigma_m * defaults.model.track_sigma_m;
  /* from (0.5, 1) north: 2 m; S = P_dd + sigma^2 (the echo at s = 0.5 from c: + s^2 P_tt) */
  struct wall_detector_map_beam b = beam(0.5f, 1.f, 0.f);
  struct wall_detector_map_prediction p = predict(&b);
  assert_true(p.known);
  assert_close(p.range_m, 2.0, 1e-6);
  /* t = (n_y, -n_x) = (1, 0): s = 0.5 */
  assert_close(p.var_m2, 0.0004 + 0.25 * 0.0001 + sigma2, 1e-7);
  /* at 30 deg: north wall at 2 / cos 30 = 2.309 m (s = 0.5 + 2.309 sin 30 = 1.655, within 1 + reach), east wall at
   * 1.5 / cos 60 = 3 m: the north one; S = (P_dd + s^2 P_tt) / cos^2 30 + sigma^2 */
  b = beam(0.5f, 1.f, 30.f);
  p = predict(&b);
  assert_close(p.range_m, 2.0 / cos(M_PI / 6.0), 1e-5);
  const double s_m = 0.5 + 2.0 / cos(M_PI / 6.0) * 0.5;
  assert_close(p.var_m2, (0.0004 + s_m * s_m * 0.0001) / (cos(M_PI / 6.0) * cos(M_PI / 6.0)) + sigma2, 1e-6);
  /* at 60 deg: east wall 1.5 / cos 30 = 1.732 m, north wall 2 / cos 60 = 4 m: the east one */
  b = beam(0.5f, 1.f, 60.f);
  assert_close(predict(&b).range_m, 1.5 / cos(M_PI / 6.0), 1e-5);
  /* beyond the north wall's reach (x = 2.5: s = 2.5 > 1 + 1) it predicts nothing; the east wall is behind */
  b = beam(-2.5f, 1.f, 0.f);
  assert_false(predict(&b).known);
  /* steeper than 75 deg from the normal: no echo comes back */
  b = beam(0.f, 2.9f, 80.f);
  assert_false(predict(&b).known);
  /* a line behind the beam is not met */
  b = beam(0.f, 1.f, 180.f);
  assert_false(predict(&b).known);
}

static void the_offset_variance_grows_with_the_drift(void **state)
{
  (void)state;
  put_line(0, 0.f, 3.f, 0.f, -1.f, 1.f);
  const struct wall_detector_map_beam b = beam(0.f, 1.f, 0.f);
  const float sigma2 = defaults.model.track_sigma_m * defaults.model.track_sigma_m;
  const struct wall_detector_map_prediction later = wall_detector_map_predict(&map, &defaults.map, &defaults.model,
      &b, 11000000u);
  assert_close(later.var_m2, 0.0004 + defaults.map.drift_m2_per_s * 10.0 + sigma2, 1e-6);
  assert_close(later.range_m, 2.0, 1e-6);
}

/** g by its formula (wall_detector_map.h), in double. */
static double expected_g(double range_m, double r0_m, double var_m2)
{
  const struct wall_detector_map_params *m = &defaults.map;
  const double span_m = defaults.model.sonar_max_m - defaults.model.sonar_min_m;
  const double z = (range_m - r0_m) / sqrt(var_m2);
  const double at_line = exp(-0.5 * z * z) / sqrt(2.0 * M_PI * var_m2);
  const double in_bulge = range_m >= r0_m - m->bulge_m && range_m <= r0_m ? 1.0 / m->bulge_m : 0.0;
  const double keep = 1.0 - defaults.model.outlier_prob;
  return log(keep * span_m * ((1.0 - m->bulge_prob) * at_line + m->bulge_prob * in_bulge) + 1.0 - keep);
}

static void what_the_map_says_about_a_reading(void **state)
{
  (void)state;
  const struct wall_detector_map_prediction p = { .known = true, .range_m = 1.5f, .var_m2 = 0.0029f };
  /* defaults: span 2.8 m, outlier 0.1, bulge 0.5 m with probability 0.3. At the line: 0.9 x 2.8 x (0.7 / sqrt(2 pi
   * 0.0029) + 0.3 / 0.5) + 0.1 = 0.9 x 2.8 x (0.7 x 7.408 + 0.6) + 0.1 = 14.68, g = 2.687; 0.3 m in front (a bulge,
   * 5.6 sd): 0.9 x 2.8 x 0.6 + 0.1, g = 0.478; 0.8 m in front (a body): log 0.1 */
  assert_close(map_llr(&p, 1.5f), expected_g(1.5, 1.5, 0.0029), 1e-5);
  assert_close(map_llr(&p, 1.5f), 2.687, 1e-3);
  assert_close(map_llr(&p, 1.2f), expected_g(1.2, 1.5, 0.0029), 1e-5);
  assert_close(map_llr(&p, 1.2f), log(0.9 * 2.8 * 0.6 + 0.1), 1e-3);
  assert_close(map_llr(&p, 0.7f), log(0.1), 1e-6);
  assert_close(map_llr(&p, 1.55f), expected_g(1.55, 1.5, 0.0029), 1e-5);
  /* a reading clamped at the minimum, the line at 0.5 m: P(reading <= 0.2 | line) = 0.7 Phi((0.2 - 0.5) / sd) +
   * 0.3 (0.2 - 0.0) / 0.5, over the wall's clamped probability */
  const struct wall_detector_map_prediction near = { .known = true, .range_m = 0.5f, .var_m2 = 0.0029f };
  const double line_p = 0.5 * erfc(0.3 / sqrt(2.0 * 0.0029));
  const double ratio = (0.7 * line_p + 0.3 * 0.4) / terms.clamped_wall_p;
  assert_close(map_llr(&near, defaults.model.sonar_min_m),
               log(0.9 * ratio + 0.1), 1e-5);
}

/** Learn a wall echo read range_m from (x, y) at bearing_deg at t_us, judged as `wall`, explained by `by`. */
static void learn(float x_m, float y_m, float bearing_deg, float range_m, bool wall, uint32_t by, uint32_t t_us)
{
  const struct wall_detector_map_beam b = beam(x_m, y_m, bearing_deg);
  wall_detector_map_learn(&map, &defaults.map, &defaults.model, &b, range_m, wall, true, by, 0u, t_us);
}

static void a_line_is_a_wall_once_no_one_peer_explains_its_echoes(void **state)
{
  (void)state;
  const struct wall_detector_map_beam b = beam(0.f, 0.f, 0.f);
  /* three echoes no peer explains: a line, not yet confirmed (WALL_DETECTOR_MAP_CONFIRM = 4) */
  for (int i = 0; i < 3; i++) {
    learn(0.f, 0.f, 0.f, 1.5f, false, 0u, 1000000u + 50000u * i);
  }
  assert_true(map.line[0].used);
  assert_false(predict(&b).known);
  learn(0.f, 0.f, 0.f, 1.5f, false, 0u, 1150000u);
  assert_true(wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, 1150000u).known);
  /* echoes seen with no peer in range (before the ranging runs) do not count: still unconfirmed */
  memset(&map, 0, sizeof(map));
  for (int i = 0; i < 10; i++) {
    const struct wall_detector_map_beam alone = beam(0.f, 0.f, 0.f);
    wall_detector_map_learn(&map, &defaults.map, &defaults.model, &alone, 1.5f, true, false, 0u, 0u,
                            1000000u + 50000u * i);
  }
  assert_true(map.line[0].used);
  assert_false(wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, 1500000u).known);
  /* a body that stays still, judged a wall, its echoes all explained by peer slot 2: never a wall */
  memset(&map, 0, sizeof(map));
  for (int i = 0; i < 50; i++) {
    learn(0.f, 0.f, 0.f, 1.5f, true, 1u << 2, 1000000u + 50000u * i);
  }
  assert_int_equal(map.line[0].echoes, 50);
  assert_int_equal(map.line[0].explained[2], 50);
  assert_false(wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, 3500000u).known);
  /* ... until peer 2 explained at most 90 % of them (the share of a body's peer, WALL_DETECTOR_MAP_BODY_SHARE):
   * 46 explained and 5 not is 46 of 51, 90.2 %; one more not explained is 46 of 52, 88.5 % */
  memset(&map, 0, sizeof(map));
  uint32_t t_us = 1000000u;
  for (int i = 0; i < 46; i++, t_us += 50000u) {
    learn(0.f, 0.f, 0.f, 1.5f, true, 1u << 2, t_us);
  }
  for (int i = 0; i < 5; i++, t_us += 50000u) {
    learn(0.f, 0.f, 0.f, 1.5f, true, 0u, t_us);
  }
  assert_false(wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, t_us).known);
  learn(0.f, 0.f, 0.f, 1.5f, true, 0u, t_us);
  assert_true(wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, t_us).known);
}

static void only_walls_and_unexplained_echoes_teach(void **state)
{
  (void)state;
  /* explained by a peer and not judged a wall: nothing learned */
  learn(0.f, 0.f, 0.f, 1.5f, false, 1u, 1000000u);
  assert_false(map.line[0].used);
  /* judged a wall, or explained by no peer: learned */
  learn(0.f, 0.f, 0.f, 1.5f, true, 1u, 1000000u);
  assert_true(map.line[0].used);
  learn(0.f, 0.f, 90.f, 1.5f, false, 0u, 1000000u);
  assert_true(map.line[1].used);
  /* closer than a body's width (2 radii): a body in contact is as likely; nothing learned */
  learn(0.f, 0.f, 180.f, 0.39f, true, 0u, 1000000u);
  assert_false(map.line[2].used);
}

static void an_echo_in_front_of_a_confirmed_line_starts_no_line(void **state)
{
  (void)state;
  /* a line of 3 echoes, unconfirmed: an echo in its bulge (0.3 m in front) starts no other line, one well in front
   * of it does (a second wall nearer on this beam, or the first was a body) */
  for (int i = 0; i < 3; i++) {
    learn(0.f, 0.f, 0.f, 1.5f, true, 0u, 1000000u + 50000u * i);
  }
  learn(0.f, 0.f, 0.f, 1.2f, true, 0u, 1150000u);
  assert_false(map.line[1].used);
  learn(0.f, 0.f, 0.f, 0.7f, true, 0u, 1200000u);
  assert_true(map.line[1].used);
  /* confirmed (4 echoes): an echo anywhere in front of it comes from a body between (a hovering peer whose grazing
   * echoes its ranging does not explain) or the bulge, and starts no line */
  memset(&map, 0, sizeof(map));
  for (int i = 0; i < 4; i++) {
    learn(0.f, 0.f, 0.f, 1.5f, true, 0u, 1000000u + 50000u * i);
  }
  learn(0.f, 0.f, 0.f, 0.7f, false, 0u, 1200000u);
  assert_false(map.line[1].used);
  assert_int_equal(map.line[0].echoes, 4);
}

static void an_echo_a_peer_explains_fuses_only_into_a_sharp_line(void **state)
{
  (void)state;
  /* a wall 2 m north, seen at 1 s: an echo judged a wall that peer slot 0 explains fuses (prediction sd
   * sqrt(0.0004 + 0.0025) = 0.054 m, below twice the ranging's 0.12 m) */
  put_line(0, 0.f, 2.f, 0.f, -1.f, 1.f);
  learn(0.f, 0.f, 0.f, 1.98f, true, 1u, 1000000u);
  assert_int_equal(map.line[0].echoes, 101);
  /* 10 s later its offset has diffused (sd sqrt(0.08 + 0.0025 + ...) = 0.29 m): such an echo 0.5 m in front (z = -1.7,
   * within the gate) no longer moves it, the peer is the likelier source */
  const float c_y_m = map.line[0].c_y_m;
  learn(0.f, 0.f, 0.f, 1.5f, true, 1u, 11000000u);
  assert_int_equal(map.line[0].echoes, 101);
  assert_close(map.line[0].c_y_m, c_y_m, 1e-6);
  /* the same echo explained by no peer does */
  learn(0.f, 0.f, 0.f, 1.5f, true, 0u, 11000000u);
  assert_int_equal(map.line[0].echoes, 102);
  assert_true(map.line[0].c_y_m < c_y_m - 0.3f);
}

static void an_echo_from_beyond_a_line_where_it_was_seen_forgets_it(void **state)
{
  (void)state;
  put_line(0, 0.f, 3.f, 0.f, -1.f, 1.f);
  /* from x = 1.5 (s = 1.5: met, within the reach, but beyond the extent and a body radius) an echo from farther
   * leaves it */
  learn(1.5f, 1.f, 0.f, 2.5f, false, 1u, 1000000u);
  assert_true(map.line[0].used);
  /* within the extent it shows the line was no wall */
  learn(0.5f, 1.f, 0.f, 2.5f, false, 1u, 1000000u);
  assert_false(map.line[0].used);
}

static void a_new_line_takes_a_free_place_then_the_least_confirmed(void **state)
{
  (void)state;
  for (int i = 0; i < WALL_DETECTOR_MAP_LINES; i++) {
    put_line(i, 10.f * (float)(i + 1), 50.f, 0.f, -1.f, 1.f);   // far north-east: no beam below meets them
    map.line[i].stamp_us = 1000000u + (uint32_t)i;
  }
  map.line[5].echoes = 2;                  // the only unconfirmed one
  learn(0.f, 0.f, 0.f, 1.5f, true, 0u, 2000000u);
  assert_close(map.line[5].c_y_m, 1.5, 1e-6);
  map.line[5].echoes = 100;
  learn(0.f, 0.f, 90.f, 1.5f, true, 0u, 2000000u);   // all confirmed: the one fused longest ago, line 0
  assert_close(map.line[0].c_x_m, 1.5, 1e-6);
}

/*
 * The Kalman filter of a line against a brute-force search of the posterior it approximates. A copter flies past
 * an oblique wall (normal bearing 20 deg through (0, 3)) along y = 1 from x = -1 to 1, its front sonar (bearing 0)
 * reading the wall with Gaussian noise of sd track_sigma_m; no drift. The posterior of the line (its point on the
 * first echo's beam, theta) is the first echo's likelihood (the line through it: offset sd sigma) times the later
 * echoes' likelihoods times the prior of theta, N(0 deg, angle_sd^2):
 *   J(rho, theta) = sum_i (r_i - r_i(rho, theta))^2 / sigma^2 + theta^2 / angle_sd^2,
 * rho the line's offset along the first beam from the copter's first position. A grid search refined 6 times
 * finds its minimum; the filter's line must predict within 5 mm of it along the path's beams and its angle within
 * 0.5 deg (the filter linearises; the wall is 20 deg off its prior). Seed 31, 41 echoes.
 */
struct path_echo {
  float x_m, y_m, range_m;
};

static double line_range(double rho_m, double theta_rad, double x_m, double y_m)
{
  /* the line through (x0, y0 + rho) = (-1, 1 + rho) with normal (sin theta, cos theta); the beam points north */
  const double n_x = sin(theta_rad), n_y = cos(theta_rad);
  return (n_x * (-1.0 - x_m) + n_y * (1.0 + rho_m - y_m)) / n_y;
}

static double posterior_cost(const struct path_echo *echo, int n, double rho_m, double theta_rad)
{
  const double sigma_m = defaults.model.track_sigma_m, angle_sd = defaults.map.angle_sd_rad;
  double j = theta_rad * theta_rad / (angle_sd * angle_sd);
  for (int i = 0; i < n; i++) {
    const double e = echo[i].range_m - line_range(rho_m, theta_rad, echo[i].x_m, echo[i].y_m);
    j += e * e / (sigma_m * sigma_m);
  }
  return j;
}

static void the_kalman_filter_finds_the_posteriors_line(void **state)
{
  (void)state;
  defaults.map.drift_m2_per_s = 0.f;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 31);
  enum { N = 41 };
  struct path_echo echo[N];
  const double wall_theta = 20.0 * M_PI / 180.0;
  for (int i = 0; i < N; i++) {
    const double x_m = -1.0 + 2.0 * i / (N - 1), y_m = 1.0;
    /* the wall n . (q - (0, 3)) = 0 read along north: r = (n_x (0 - x) + n_y (3 - y)) / n_y */
    const double true_m = (sin(wall_theta) * -x_m + cos(wall_theta) * (3.0 - y_m)) / cos(wall_theta);
    echo[i] = (struct path_echo) { (float)x_m, (float)y_m,
                                   (float)(true_m + gsl_ran_gaussian(rng, defaults.model.track_sigma_m)) };
    learn(echo[i].x_m, echo[i].y_m, 0.f, echo[i].range_m, true, 0u, 1000000u + 50000u * (uint32_t)i);
  }
  gsl_rng_free(rng);
  assert_true(map.line[0].used);
  assert_false(map.line[1].used);
  /* brute force: a grid of 41 x 41 around the best point, the step divided by 4 six times */
  double best_rho = echo[0].range_m, best_theta = 0.0, step_rho = 0.2, step_theta = 0.05;
  for (int round = 0; round < 7; round++) {
    double centre_rho = best_rho, centre_theta = best_theta, best_j = INFINITY;
    for (int a = -20; a <= 20; a++) {
      for (int b = -20; b <= 20; b++) {
        const double rho = centre_rho + a * step_rho, theta = centre_theta + b * step_theta;
        const double j = posterior_cost(echo, N, rho, theta);
        if (j < best_j) {
          best_j = j;
          best_rho = rho;
          best_theta = theta;
        }
      }
    }
    step_rho /= 4.0;
    step_theta /= 4.0;
  }
  print_message("# posterior mode: theta %.4f deg; filter: %.4f deg\n", best_theta * 180.0 / M_PI,
                map.line[0].theta_rad * 180.0 / M_PI);
  assert_close(map.line[0].theta_rad, best_theta, 0.5 * M_PI / 180.0);
  for (int i = 0; i < N; i += 10) {
    const struct wall_detector_map_beam b = beam(echo[i].x_m, echo[i].y_m, 0.f);
    const double filter_m = wall_detector_map_predict(&map, &defaults.map, &defaults.model, &b, 4000000u).range_m;
    assert_close(filter_m, line_range(best_rho, best_theta, echo[i].x_m, echo[i].y_m), 0.005);
  }
  /* and near the truth: within 3 deg, 3.7 sd (theta's posterior sd is about sigma / (sqrt(N) x sd of the copter's x)
   * = 0.05 / (6.4 x 0.577) = 0.8 deg) */
  assert_close(best_theta, wall_theta, 3.0 * M_PI / 180.0);
}

static void the_map_is_small(void **state)
{
  (void)state;
  /* what flies on a Cortex-M4: 8 lines of 48 bytes and two counters per peer slot, within 1 KB (wall_detector_map.h) */
  print_message("# the map: %zu bytes\n", sizeof(struct wall_detector_map));
  assert_true(sizeof(struct wall_detector_map) <= 1024);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup(a_beam_meets_the_nearest_line_within_its_reach, setup),
    cmocka_unit_test_setup(the_offset_variance_grows_with_the_drift, setup),
    cmocka_unit_test_setup(what_the_map_says_about_a_reading, setup),
    cmocka_unit_test_setup(a_line_is_a_wall_once_no_one_peer_explains_its_echoes, setup),
    cmocka_unit_test_setup(only_walls_and_unexplained_echoes_teach, setup),
    cmocka_unit_test_setup(an_echo_in_front_of_a_confirmed_line_starts_no_line, setup),
    cmocka_unit_test_setup(an_echo_a_peer_explains_fuses_only_into_a_sharp_line, setup),
    cmocka_unit_test_setup(an_echo_from_beyond_a_line_where_it_was_seen_forgets_it, setup),
    cmocka_unit_test_setup(a_new_line_takes_a_free_place_then_the_least_confirmed, setup),
    cmocka_unit_test_setup(the_kalman_filter_finds_the_posteriors_line, setup),
    cmocka_unit_test_setup(the_map_is_small, setup),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
