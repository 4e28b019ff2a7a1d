/*
 * The wall detector's tabulated llr (wall_detector_llr_table.h) against the exact llr (wall_detector_reading_llr)
 * on a dense grid of readings and peer distances over the whole domain (readings above the sonar minimum and below
 * its maximum, distances from 0 to the ranging maximum): the largest error must stay below the stated bound
 * WALL_DETECTOR_LLR_TABLE_TOLERANCE = 1e-3 (the default model's: 5.8e-4, printed) and below the bound the table
 * estimated when it was built. Deterministic (no random draws). The grid's steps (1.4 mm and 1.8 mm, against table
 * steps of 4.1 mm and 2.4 mm) put readings and distances at every phase within the tables' intervals, so a table
 * twice as coarse (error x 4) or shifted by a fraction of a step fails the bound. The same for the table of a reading
 * clamped to the sonar minimum (distances 25 um apart): for the default model, and for a 5 m ranging maximum, whose
 * coarser clamped table sets the table's bound itself; beyond its ends it reads the ends' values. Also: one table per
 * model, shared; a model the table cannot resolve and a model changed by a setting after init fall back to the exact
 * llr.
 */
#include "test_helpers.h"
#include "wall_detector_fixtures.h"

/** The stated bound of the llr error (README; the table's WALL_DETECTOR_LLR_TABLE_TOLERANCE), a literal here so
 * that a coarser table with a raised tolerance still fails */
#define STATED_LLR_ERROR 1e-3

/** The module's default model and its terms, as wall_detector_init() sets them from the defines. */
static struct wall_detector_params defaults;
static struct wall_detector_model_terms default_terms;

static int setup(void **state)
{
  (void)state;
  defaults = wall_detector_default_params();
  wall_detector_model_terms_init(&default_terms, &defaults.model);
  return 0;
}

/** Largest |table llr - exact llr| over the grid (readings every 1.4 mm, distances every 1.8 mm). */
static double largest_error(const struct wall_detector_llr_table *table, const struct wall_detector_model_terms *terms)
{
  enum { READINGS = 2001, DISTANCES = 1401 };
  const struct wall_detector_model *m = &terms->model;
  double largest = 0.0;
  float worst_range_m = 0.f, worst_peer_m = 0.f;
  for (int i = 0; i < READINGS; i++) {
    /* strictly inside (min, max): a reading at the minimum is clamped (exact, cached), at the maximum no echo */
    const float range_m = m->sonar_min_m + (m->sonar_max_m - m->sonar_min_m) * (i + 0.5f) / READINGS;
    for (int j = 0; j < DISTANCES; j++) {
      const float peer_m = m->ranging_max_m * j / DISTANCES;
      const double error = fabs((double)wall_detector_llr_table_llr(table, range_m, peer_m) -
                                wall_detector_reading_llr(terms, range_m, peer_m));
      if (error > largest) {
        largest = error;
        worst_range_m = range_m;
        worst_peer_m = peer_m;
      }
    }
  }
  print_message("# largest llr error %.3g at reading %.4f m, peer %.4f m (table's estimate %.3g)\n", largest,
                worst_range_m, worst_peer_m, table->error_bound);
  return largest;
}

static void the_table_llr_is_within_the_bound_of_the_exact_llr(void **state)
{
  (void)state;
  const struct wall_detector_llr_table *table = wall_detector_llr_table_shared(&default_terms);
  assert_non_null(table);
  const double error = largest_error(table, &default_terms);
  assert_true(error <= STATED_LLR_ERROR);
  assert_true(error <= table->error_bound);
  /* the estimate is not loose either: a coarser table's would exceed the tolerance */
  assert_true(table->error_bound <= 2.0 * error);
}

/** Largest |table llr - exact llr| of a reading clamped to the sonar minimum, against 100002 peer distances over
 * [0, ranging max] (25 um apart for the default 2.5 m, against table steps of 4.9 mm). */
static double largest_clamped_error(const struct wall_detector_llr_table *table,
                                    const struct wall_detector_model_terms *terms)
{
  const struct wall_detector_model *m = &terms->model;
  double largest = 0.0;
  float worst_m = 0.f;
  enum { DISTANCES = 100001 };
  for (int j = 0; j <= DISTANCES; j++) {
    const float peer_m = m->ranging_max_m * j / DISTANCES;
    const double error = fabs((double)wall_detector_llr_table_clamped_llr(table, peer_m) -
                              wall_detector_reading_llr(terms, m->sonar_min_m, peer_m));
    if (error > largest) {
      largest = error;
      worst_m = peer_m;
    }
  }
  print_message("# ranging max %.2f m: largest clamped llr error %.3g at peer %.4f m (table's estimate %.3g)\n",
                m->ranging_max_m, largest, worst_m, table->error_bound);
  return largest;
}

/** The default model with another ranging maximum: its terms and its llr table. */
static void build_with_ranging_max(float ranging_max_m, struct wall_detector_model_terms *terms,
                                   struct wall_detector_llr_table *table)
{
  struct wall_detector_model model = default_terms.model;
  model.ranging_max_m = ranging_max_m;
  wall_detector_model_terms_init(terms, &model);
  wall_detector_llr_table_build(table, terms);
}

static void the_clamped_llr_is_within_the_bound_of_the_exact_llr(void **state)
{
  (void)state;
  /* the default table: within the stated 1e-3 and the table's bound (which its parts' error sets here) */
  const struct wall_detector_llr_table *table = wall_detector_llr_table_shared(&default_terms);
  assert_non_null(table);
  const double error = largest_clamped_error(table, &default_terms);
  assert_true(error <= STATED_LLR_ERROR);
  assert_true(error <= table->error_bound);
  assert_true(error > 0.0);
  /* a 5 m ranging maximum: the clamped table's steps are twice as long, its error four times the default's, above
   * the parts' error (8.6e-4), so its own estimate is the table's bound: the error is within it, and not loose */
  struct wall_detector_model_terms far_terms;
  static struct wall_detector_llr_table far_table;
  build_with_ranging_max(5.f, &far_terms, &far_table);
  const double far_error = largest_clamped_error(&far_table, &far_terms);
  assert_true(far_error > table->error_bound);
  assert_true(far_error <= far_table.error_bound && far_table.error_bound <= 2.0 * far_error);
}

static void the_clamped_llr_beyond_the_table_is_that_at_its_ends(void **state)
{
  (void)state;
  /* a 0.45 m ranging maximum, where the clamped llr still changes (the peer's echo reaches the sonar minimum at
   * 0.41 m): a distance beyond either end of the table reads the end's value, not the line of the last interval
   * drawn on */
  struct wall_detector_model_terms near_terms;
  static struct wall_detector_llr_table near_table;
  build_with_ranging_max(0.45f, &near_terms, &near_table);
  const float ranging_max_m = near_terms.model.ranging_max_m;
  const float at_end = wall_detector_llr_table_clamped_llr(&near_table, ranging_max_m);
  print_message("# clamped llr at the ends %.6f, %.6f\n", wall_detector_llr_table_clamped_llr(&near_table, 0.f),
                at_end);
  assert_true(at_end != wall_detector_llr_table_clamped_llr(&near_table, 0.99f * ranging_max_m));
  assert_true(wall_detector_llr_table_clamped_llr(&near_table, ranging_max_m + 1.f) == at_end);
  assert_true(wall_detector_llr_table_clamped_llr(&near_table, -1.f) ==
              wall_detector_llr_table_clamped_llr(&near_table, 0.f));
}

static void a_model_the_table_cannot_resolve_uses_the_exact_llr(void **state)
{
  (void)state;
  /* Rayleigh sigma 0.5 m with a ranging sigma of 0.01 m: the table spans +-8 x 0.5 m in steps of 16 mm, coarser
   * than the ranging error that smooths the Rayleigh density's kink at 0 */
  struct wall_detector_params sharp = defaults;
  sharp.model.sonar_sigma_m = 0.5f;
  sharp.model.ranging_sigma_m = 0.01f;
  struct wall_detector_model_terms terms;
  wall_detector_model_terms_init(&terms, &sharp.model);
  assert_null(wall_detector_llr_table_shared(&terms));
  static struct wall_detector_llr_table coarse;
  wall_detector_llr_table_build(&coarse, &terms);
  assert_true(coarse.error_bound > WALL_DETECTOR_LLR_TABLE_TOLERANCE);
  assert_true(largest_error(&coarse, &terms) > WALL_DETECTOR_LLR_TABLE_TOLERANCE);
  static struct wall_detector_filter filter;
  wall_detector_filter_init(&filter, &sharp);
  assert_null(filter.llr_table);
  assert_true(wall_detector_filter_reading_llr(&filter, 1.3f, 1.5f) ==
              wall_detector_reading_llr(&terms, 1.3f, 1.5f));
}

static void one_table_per_model_is_shared_and_a_changed_model_is_judged_exactly(void **state)
{
  (void)state;
  /* every copter of the default model gets the same table */
  static struct wall_detector_filter first, second;
  wall_detector_filter_init(&first, &defaults);
  wall_detector_filter_init(&second, &defaults);
  assert_non_null(first.llr_table);
  assert_ptr_equal(first.llr_table, second.llr_table);
  assert_ptr_equal(wall_detector_llr_table_find(&defaults.model), first.llr_table);
  /* the pool (2: the default and the unresolvable model above) is full: another model gets none */
  struct wall_detector_params other = defaults;
  other.model.ranging_sigma_m = 0.15f;
  struct wall_detector_model_terms other_terms;
  wall_detector_model_terms_init(&other_terms, &other.model);
  assert_null(wall_detector_llr_table_shared(&other_terms));
  /* a setting changes the second copter's model after init: it judges with the exact llr, the first keeps the
   * table */
  second.params.model.ranging_sigma_m = 0.15f;
  const struct wall_detector_pose pose = { 0.f, 0.f, 0.f };
  struct wall_detector_decision d;
  wall_detector_filter_sonar(&second, 0, 1.3f, &pose, 1000000u, &d);
  assert_null(second.llr_table);
  assert_true(wall_detector_filter_reading_llr(&second, 1.3f, 1.5f) ==
              wall_detector_reading_llr(&other_terms, 1.3f, 1.5f));
  assert_true(wall_detector_filter_reading_llr(&first, 1.3f, 1.5f) ==
              wall_detector_llr_table_llr(first.llr_table, 1.3f, 1.5f));
  /* and back to the default model: the shared table again */
  second.params.model.ranging_sigma_m = defaults.model.ranging_sigma_m;
  wall_detector_filter_sonar(&second, 0, 1.3f, &pose, 1050000u, &d);
  assert_ptr_equal(second.llr_table, first.llr_table);
}

int main(void)
{
  /* in this order: the pool fills as the tests go (default model, unresolvable model) */
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_table_llr_is_within_the_bound_of_the_exact_llr),
    cmocka_unit_test(the_clamped_llr_is_within_the_bound_of_the_exact_llr),
    cmocka_unit_test(the_clamped_llr_beyond_the_table_is_that_at_its_ends),
    cmocka_unit_test(a_model_the_table_cannot_resolve_uses_the_exact_llr),
    cmocka_unit_test(one_table_per_model_is_shared_and_a_changed_model_is_judged_exactly),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
