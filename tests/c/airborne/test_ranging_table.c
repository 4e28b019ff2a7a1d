/* The per-peer ranging table: newest value per peer, freshness, bounded size. Exact. */
#include "test_helpers.h"
#include "modules/ranging/ranging_table.h"

static void keeps_the_newest_distance_per_peer(void **state)
{
  (void)state;
  struct ranging_table t;
  ranging_table_init(&t, 500000);
  ranging_table_update(&t, 3, 1.0f, 100);
  ranging_table_update(&t, 4, 2.0f, 110);
  ranging_table_update(&t, 3, 1.2f, 200);
  const struct ranging_peer *p = ranging_table_find(&t, 3);
  assert_non_null(p);
  assert_close(p->distance_m, 1.2f, 0.0);
  assert_int_equal(p->stamp_us, 200);
  assert_int_equal(p->count, 2);
  assert_null(ranging_table_find(&t, 5));
  assert_null(ranging_table_find(&t, 0));
}

static void a_stale_distance_is_not_fresh(void **state)
{
  (void)state;
  struct ranging_table t;
  ranging_table_init(&t, 500000);
  const struct ranging_peer *p = ranging_table_update(&t, 3, 1.0f, 1000000);
  assert_true(ranging_table_is_fresh(&t, p, 1499999));
  assert_false(ranging_table_is_fresh(&t, p, 1500000));
  float out[4];
  assert_int_equal(ranging_table_fresh_distances(&t, 1600000, out, 4), 0);
  assert_false(ranging_table_is_fresh(&t, NULL, 0));
}

static void a_full_table_replaces_the_peer_heard_longest_ago(void **state)
{
  (void)state;
  struct ranging_table t;
  ranging_table_init(&t, 500000);
  for (unsigned i = 0; i < RANGING_TABLE_MAX_PEERS; i++) {
    ranging_table_update(&t, (uint8_t)(i + 1), 1.0f, 1000 + (i == 7 ? 0 : 10 * i + 10));
  }
  ranging_table_update(&t, 200, 2.0f, 5000);
  assert_null(ranging_table_find(&t, 8));          /* peer 8 (index 7) was the oldest */
  assert_non_null(ranging_table_find(&t, 200));
  assert_non_null(ranging_table_find(&t, 1));
  float out[RANGING_TABLE_MAX_PEERS];
  assert_int_equal(ranging_table_fresh_distances(&t, 5000, out, RANGING_TABLE_MAX_PEERS), RANGING_TABLE_MAX_PEERS);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(keeps_the_newest_distance_per_peer),
    cmocka_unit_test(a_stale_distance_is_not_fresh),
    cmocka_unit_test(a_full_table_replaces_the_peer_heard_longest_ago),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
