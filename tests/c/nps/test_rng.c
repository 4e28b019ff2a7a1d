/*
 * Random streams (nps_rng.h): same seed, same stream; different (vehicle, sensor) or seed, independent streams.
 * Statistical conventions in test_effect_stats.h. Here: N_DRAWS = 200000 uniforms per stream;
 * correlation |r| <= K_SIGMA / sqrt(N) (SE of r under independence: 1 / sqrt(N)); a 16 x 16 chi-square of
 * paired draws and KS uniformity at KS_ALPHA = 1e-4.
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <string.h>
#include <gsl/gsl_cdf.h>

#include "nps_rng.h"

#define N_DRAWS 200000
#define RUN_SEED 20260101ull

static double *draw_uniforms(uint64_t seed, uint64_t vehicle, uint64_t sensor)
{
  gsl_rng *r = nps_rng_stream_new(seed, vehicle, sensor);
  assert_non_null(r);
  double *u = malloc(N_DRAWS * sizeof(double));
  for (size_t i = 0; i < N_DRAWS; i++) {
    u[i] = gsl_rng_uniform(r);
  }
  gsl_rng_free(r);
  return u;
}

static void same_seed_gives_the_same_stream(void **state)
{
  (void)state;
  double *a = draw_uniforms(RUN_SEED, 3, NPS_RNG_SENSOR_SONAR_LEFT);
  double *b = draw_uniforms(RUN_SEED, 3, NPS_RNG_SENSOR_SONAR_LEFT);
  assert_memory_equal(a, b, N_DRAWS * sizeof(double));
  free(a);
  free(b);
}

static void mix64_is_splitmix64(void **state)
{
  (void)state;
  /* SplitMix64 seeded with 0 outputs mix64(golden) = 0xE220A8397B1DCDAF first (Vigna's reference code). */
  assert_true(nps_rng_mix64(0x9E3779B97F4A7C15ull) == 0xE220A8397B1DCDAFull);
}

static double uniform_cdf(double x, const void *p)
{
  (void)p;
  return fmin(fmax(x, 0.0), 1.0);
}

static double pearson(const double *a, const double *b, size_t n)
{
  double ma = stats_mean(a, n), mb = stats_mean(b, n), sab = 0.0, saa = 0.0, sbb = 0.0;
  for (size_t i = 0; i < n; i++) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / sqrt(saa * sbb);
}

/** Chi-square p-value of the joint 16 x 16 histogram of (a[i], b[i]) against independence of uniforms. */
static double pair_chisq_p(const double *a, const double *b, size_t n)
{
  enum { BINS = 16 };
  static double count[BINS][BINS];
  memset(count, 0, sizeof(count));
  for (size_t i = 0; i < n; i++) {
    count[(int)(a[i] * BINS)][(int)(b[i] * BINS)] += 1.0;
  }
  double expected = (double)n / (BINS * BINS), chi2 = 0.0;
  for (int i = 0; i < BINS; i++) {
    for (int j = 0; j < BINS; j++) {
      chi2 += (count[i][j] - expected) * (count[i][j] - expected) / expected;
    }
  }
  return gsl_cdf_chisq_Q(chi2, BINS * BINS - 1);
}

static void assert_independent(uint64_t seed_a, uint64_t veh_a, uint64_t sen_a,
                               uint64_t seed_b, uint64_t veh_b, uint64_t sen_b)
{
  double *a = draw_uniforms(seed_a, veh_a, sen_a);
  double *b = draw_uniforms(seed_b, veh_b, sen_b);
  double bound = K_SIGMA / sqrt((double)N_DRAWS);
  assert_close(pearson(a, b, N_DRAWS), 0.0, bound);
  assert_close(pearson(a, b + 1, N_DRAWS - 1), 0.0, bound);   /* b one draw ahead */
  assert_close(pearson(a + 1, b, N_DRAWS - 1), 0.0, bound);   /* a one draw ahead */
  double p = pair_chisq_p(a, b, N_DRAWS);
  assert_true(p >= KS_ALPHA);
  assert_ks_accepts(stats_ks_test(a, N_DRAWS, uniform_cdf, NULL));
  assert_ks_accepts(stats_ks_test(b, N_DRAWS, uniform_cdf, NULL));
  free(a);
  free(b);
}

static void neighbouring_vehicles_are_independent(void **state)
{
  (void)state;
  assert_independent(RUN_SEED, 0, NPS_RNG_SENSOR_SONAR_FRONT, RUN_SEED, 1, NPS_RNG_SENSOR_SONAR_FRONT);
}

static void sensors_of_one_vehicle_are_independent(void **state)
{
  (void)state;
  assert_independent(RUN_SEED, 2, NPS_RNG_SENSOR_SONAR_FRONT, RUN_SEED, 2, NPS_RNG_SENSOR_SONAR_RIGHT);
  assert_independent(RUN_SEED, 2, NPS_RNG_SENSOR_RANGING_BASE + 0, RUN_SEED, 2, NPS_RNG_SENSOR_RANGING_BASE + 1);
}

static void neighbouring_seeds_are_independent(void **state)
{
  (void)state;
  assert_independent(RUN_SEED, 0, NPS_RNG_SENSOR_SONAR_FRONT, RUN_SEED + 1, 0, NPS_RNG_SENSOR_SONAR_FRONT);
}

static void the_chi_square_detects_a_dependent_pair(void **state)
{
  (void)state;
  /* power check: a stream against itself shifted by a constant is caught */
  double *a = draw_uniforms(RUN_SEED, 0, 1);
  double *b = malloc(N_DRAWS * sizeof(double));
  for (size_t i = 0; i < N_DRAWS; i++) {
    b[i] = fmod(a[i] + 0.01, 1.0);
  }
  assert_true(pair_chisq_p(a, b, N_DRAWS) < KS_ALPHA);
  free(a);
  free(b);
}

static int cmp_ulong(const void *a, const void *b)
{
  unsigned long x = *(const unsigned long *)a, y = *(const unsigned long *)b;
  return (x > y) - (x < y);
}

static void stream_seeds_do_not_collide(void **state)
{
  (void)state;
  /* every (seed, vehicle, sensor) of a 64-copter swarm with 5 sonars and 64 ranging peers, 3 run seeds */
  enum { VEHICLES = 64, SENSORS = 5 + 64, SEEDS = 3 };
  size_t n = 0;
  unsigned long *seeds = malloc(VEHICLES * SENSORS * SEEDS * sizeof(unsigned long));
  for (uint64_t s = 0; s < SEEDS; s++) {
    for (uint64_t v = 0; v < VEHICLES; v++) {
      for (uint64_t k = 0; k < SENSORS; k++) {
        uint64_t sensor = k < 5 ? NPS_RNG_SENSOR_SONAR_FRONT + k : NPS_RNG_SENSOR_RANGING_BASE + (k - 5);
        seeds[n++] = nps_rng_stream_seed(s, v, sensor);
      }
    }
  }
  qsort(seeds, n, sizeof(unsigned long), cmp_ulong);
  for (size_t i = 1; i < n; i++) {
    assert_true(seeds[i] != seeds[i - 1]);
  }
  free(seeds);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(same_seed_gives_the_same_stream),
    cmocka_unit_test(mix64_is_splitmix64),
    cmocka_unit_test(neighbouring_vehicles_are_independent),
    cmocka_unit_test(sensors_of_one_vehicle_are_independent),
    cmocka_unit_test(neighbouring_seeds_are_independent),
    cmocka_unit_test(the_chi_square_detects_a_dependent_pair),
    cmocka_unit_test(stream_seeds_do_not_collide),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
