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

/** The entry a plain scan of every entry finds for peer_id (what ranging_table_find must return). */
static const struct ranging_peer *scan_for(const struct ranging_table *t, uint16_t peer_id)
{
  for (unsigned i = 0; i < RANGING_TABLE_MAX_PEERS; i++) {
    if (peer_id != 0 && t->peers[i].id == peer_id) {
      return &t->peers[i];
    }
  }
  return NULL;
}

static void look_ups_with_the_hint_equal_a_full_scan(void **state)
{
  (void)state;
  /* 3000 updates of ids 1..300 in a fixed pseudo-random order (many ids share a hint slot, entries get replaced):
   * after each, every id 0..301 is found in the same entry as by a full scan, or in none */
  struct ranging_table t;
  ranging_table_init(&t, 500000);
  uint32_t x = 12345u;
  for (uint32_t k = 0; k < 3000; k++) {
    x = x * 1664525u + 1013904223u;   /* LCG (Numerical Recipes) */
    ranging_table_update(&t, (uint16_t)(1 + (x >> 16) % 300), 1.0f, 1000 + 10 * k);
    for (uint16_t id = 0; id <= 301; id++) {
      assert_ptr_equal(ranging_table_find(&t, id), scan_for(&t, id));
    }
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(keeps_the_newest_distance_per_peer),
    cmocka_unit_test(a_stale_distance_is_not_fresh),
    cmocka_unit_test(a_full_table_replaces_the_peer_heard_longest_ago),
    cmocka_unit_test(look_ups_with_the_hint_equal_a_full_scan),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
