/*
 * The wall detector's peer table: a peer is judged by the median of its fresh distances (the mean of the middle two
 * for an even number), checked bit for bit against the middle values of a sorted copy over 20000 random histories
 * of 1..5 distances recorded through the table, drawn with many ties (-0 and +0 among them, and negative values) and
 * at random.
 */

#include "test_helpers.h"
#include "modules/wall_detector/wall_detector_peers.h"

#include <gsl/gsl_rng.h>
#include <string.h>

/** The median of n values as a stable insertion sort finds it (the mean of the middle two). */
static float sorted_median(const float *values, int n)
{
  float d[WALL_DETECTOR_PEER_HISTORY];
  memcpy(d, values, (size_t)n * sizeof(float));
  for (int i = 1; i < n; i++) {
    const float next = d[i];
    int j = i;
    for (; j > 0 && d[j - 1] > next; j--) {
      d[j] = d[j - 1];
    }
    d[j] = next;
  }
  return 0.5f * (d[(n - 1) / 2] + d[n / 2]);
}

static void the_median_is_that_of_a_stable_sort(void **state)
{
  (void)state;
  const struct wall_detector_model model = { .ranging_max_m = 2.5f, .copter_radius_m = 0.2f };
  const float timeout_s = 0.5f;
  const float tied[] = { 0.f, -0.f, 0.5f, 0.5f, 1.f, 1.25f, 2.f, -0.5f, -1.f };
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_taus2);
  gsl_rng_set(rng, 11);
  static struct wall_detector_peers peers;
  int signed_zero_medians = 0, even = 0;
  for (int trial = 0; trial < 20000; trial++) {
    memset(&peers, 0, sizeof(peers));
    const int n = 1 + (int)gsl_rng_uniform_int(rng, WALL_DETECTOR_PEER_HISTORY);
    float values[WALL_DETECTOR_PEER_HISTORY];
    for (int i = 0; i < n; i++) {
      values[i] = trial % 2 == 0 ? tied[gsl_rng_uniform_int(rng, sizeof(tied) / sizeof(tied[0]))] :
                  (float)(2.4 * gsl_rng_uniform(rng));
      bool is_new;
      assert_int_equal(wall_detector_peers_record(&peers, 7, values[i], 1000000u + (uint32_t)i, model.ranging_max_m,
                       timeout_s, &is_new), 0);
    }
    struct wall_detector_candidates c;
    wall_detector_peers_candidates(&peers, 1000000u + (uint32_t)n, timeout_s, &model, &c);
    assert_int_equal(c.nb, 1);
    const float expected = sorted_median(values, n);
    assert_memory_equal(&c.distance_m[0], &expected, sizeof(float));
    signed_zero_medians += expected == 0.f && signbit(expected);
    even += n % 2 == 0;
  }
  gsl_rng_free(rng);
  print_message("# %d medians -0, %d of an even number of distances\n", signed_zero_medians, even);
  assert_true(signed_zero_medians > 10 && even > 5000);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_median_is_that_of_a_stable_sort),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
