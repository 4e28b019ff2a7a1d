/* Ranging receive logic (modules/ranging/ranging_can_rx.h): which frames are about this copter, the newest
 * distance per peer, freshness, sequence gaps, duplicates and restarts, and the bus state from error frames. */
#include "test_helpers.h"
#include "modules/ranging/ranging_can_rx.h"

#include <string.h>

#define SELF 5
#define STALE_US 500000

static struct ranging_can_rx rx;

static int setup(void **state)
{
  (void)state;
  const struct ranging_can_rx_config cfg = { .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = SELF, .stale_us = STALE_US };
  const char *why;
  assert_int_equal(ranging_can_rx_config_check(&cfg, &why), 0);
  ranging_can_rx_init(&rx, &cfg);
  return 0;
}

static enum ranging_can_rx_kind send(uint8_t node, uint8_t peer, uint16_t range_mm, uint16_t seq, uint32_t t_us,
                                     struct ranging_can_reading *out)
{
  const struct ranging_can_layout layout = RANGING_CAN_LAYOUT_DEFAULT;
  const struct ranging_can_msg m = { .node_id = node, .peer_id = peer, .range_mm = range_mm, .quality_pct = 80, .seq = seq };
  struct ranging_can_raw f;
  assert_int_equal(ranging_can_pack(&layout, &m, &f), RANGING_CAN_FRAME_OK);
  return ranging_can_rx_frame(&rx, &f, t_us, out);
}

static struct ranging_can_raw error_frame(uint32_t classes, uint8_t crtl)
{
  struct ranging_can_raw f = { .can_id = RANGING_CAN_ID_ERR_FLAG | classes, .len = 8 };
  f.data[1] = crtl;
  return f;
}

static void readings_about_this_copter_fill_the_table(void **state)
{
  (void)state;
  struct ranging_can_reading r;
  /* our unit measured peer 9 */
  assert_int_equal(send(SELF, 9, 1500, 1, 1000, &r), RANGING_CAN_RX_READING);
  assert_int_equal(r.other_id, 9);
  assert_int_equal(r.node_id, SELF);
  assert_close(r.range_m, 1.5, 1e-6);
  assert_int_equal(r.quality_pct, 80);
  assert_int_equal(r.stamp_us, 1000);
  /* copter 12's unit measured us: the distance to 12 */
  assert_int_equal(send(12, SELF, 2100, 40, 2000, &r), RANGING_CAN_RX_READING);
  assert_int_equal(r.other_id, 12);
  assert_int_equal(r.node_id, 12);
  /* two other copters: not ours */
  assert_int_equal(send(12, 9, 800, 41, 3000, &r), RANGING_CAN_RX_NOT_OURS);
  assert_int_equal(rx.stats.not_ours, 1);
  assert_int_equal(rx.stats.readings, 2);
  struct ranging_can_reading p;
  assert_int_equal(ranging_can_rx_peer(&rx, 9, 3000, &p), 1);
  assert_close(p.range_m, 1.5, 1e-6);
  assert_int_equal(ranging_can_rx_peer(&rx, 12, 3000, &p), 1);
  assert_close(p.range_m, 2.1, 1e-6);
  assert_int_equal(ranging_can_rx_peer(&rx, 13, 3000, &p), -1);  /* never heard */
  assert_int_equal(ranging_can_rx_peer(&rx, 200, 3000, &p), -1); /* not a node id */
}

static void the_newest_distance_wins(void **state)
{
  (void)state;
  struct ranging_can_reading p;
  for (uint16_t i = 1; i <= 10; i++) {
    assert_int_equal(send(SELF, 9, (uint16_t)(1000 + i), i, 1000U * i, NULL), RANGING_CAN_RX_READING);
  }
  assert_int_equal(ranging_can_rx_peer(&rx, 9, 10000, &p), 1);
  assert_close(p.range_m, 1.010, 1e-6);
  assert_int_equal(p.seq, 10);
  assert_int_equal(p.stamp_us, 10000);
}

static void a_stale_distance_is_never_fresh(void **state)
{
  (void)state;
  struct ranging_can_reading p;
  send(SELF, 9, 1000, 1, 1000, NULL);
  assert_int_equal(ranging_can_rx_peer(&rx, 9, 1000 + STALE_US, &p), 1);
  assert_int_equal(ranging_can_rx_peer(&rx, 9, 1000 + STALE_US + 1, &p), 0);
  assert_int_equal(p.stamp_us, 1000);  /* still filled, with its age visible */
  /* going stale is counted once */
  assert_int_equal(ranging_can_rx_check_stale(&rx, 1000 + STALE_US + 1), 1);
  assert_int_equal(ranging_can_rx_check_stale(&rx, 1000 + 2 * STALE_US), 1);
  assert_int_equal(rx.stats.stale_events, 1);
  /* a new reading makes it fresh again; a second staleness counts again */
  send(SELF, 9, 1000, 2, 2000000, NULL);
  assert_int_equal(ranging_can_rx_check_stale(&rx, 2000000), 0);
  assert_int_equal(ranging_can_rx_check_stale(&rx, 3000000), 1);
  assert_int_equal(rx.stats.stale_events, 2);
}

static void sequence_gaps_duplicates_and_restarts_are_counted(void **state)
{
  (void)state;
  assert_int_equal(send(SELF, 9, 1000, 100, 1000, NULL), RANGING_CAN_RX_READING);
  assert_int_equal(send(SELF, 9, 1000, 101, 2000, NULL), RANGING_CAN_RX_READING);
  assert_int_equal(send(SELF, 9, 1000, 105, 3000, NULL), RANGING_CAN_RX_READING);   /* 102-104 lost */
  assert_int_equal(rx.stats.seq_gaps, 1);
  assert_int_equal(rx.stats.frames_lost, 3);
  assert_int_equal(send(SELF, 9, 1111, 105, 4000, NULL), RANGING_CAN_RX_DUPLICATE);
  assert_int_equal(rx.stats.duplicates, 1);
  struct ranging_can_reading p;
  assert_int_equal(ranging_can_rx_peer(&rx, 9, 4000, &p), 1);
  assert_close(p.range_m, 1.0, 1e-6);                                                 /* the duplicate was dropped */
  assert_int_equal(send(SELF, 9, 1000, 0xFFFF, 5000, NULL), RANGING_CAN_RX_READING); /* went back: node restarted */
  assert_int_equal(send(SELF, 9, 1000, 0, 6000, NULL), RANGING_CAN_RX_READING);      /* wraps in order */
  assert_int_equal(rx.stats.node_restarts, 1);
  assert_int_equal(rx.stats.seq_gaps, 1);
  /* after a silence longer than stale_us a node starts afresh: no gap counted */
  assert_int_equal(send(SELF, 9, 1000, 9000, 6000 + STALE_US + 1, NULL), RANGING_CAN_RX_READING);
  assert_int_equal(rx.stats.seq_gaps, 1);
  assert_int_equal(rx.stats.frames_lost, 3);
  /* counters are per node: node 12's first frame is no gap */
  assert_int_equal(send(12, SELF, 1000, 7, 7000, NULL), RANGING_CAN_RX_READING);
  assert_int_equal(rx.stats.seq_gaps, 1);
}

static void invalid_frames_are_counted_by_reason(void **state)
{
  (void)state;
  struct ranging_can_raw f = { .can_id = 0x305, .len = 4 };
  assert_int_equal(ranging_can_rx_frame(&rx, &f, 0, NULL), RANGING_CAN_RX_INVALID);
  f.can_id = 0x123;
  f.len = 8;
  assert_int_equal(ranging_can_rx_frame(&rx, &f, 0, NULL), RANGING_CAN_RX_INVALID);
  assert_int_equal(rx.stats.invalid[RANGING_CAN_FRAME_BAD_DLC], 1);
  assert_int_equal(rx.stats.invalid[RANGING_CAN_FRAME_FOREIGN_ID], 1);
  assert_int_equal(rx.stats.frames, 2);
  assert_int_equal(rx.stats.readings, 0);
}

static void bus_off_and_restart_come_from_error_frames(void **state)
{
  (void)state;
  struct ranging_can_raw e = error_frame(RANGING_CAN_ERR_CRTL, RANGING_CAN_ERR_CRTL_TX_WARNING);
  assert_int_equal(ranging_can_rx_frame(&rx, &e, 0, NULL), RANGING_CAN_RX_ERROR_FRAME);
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_WARNING);
  e = error_frame(RANGING_CAN_ERR_CRTL, RANGING_CAN_ERR_CRTL_TX_PASSIVE);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_PASSIVE);
  e = error_frame(RANGING_CAN_ERR_BUSOFF, 0);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  ranging_can_rx_frame(&rx, &e, 0, NULL);  /* repeated report of the same bus-off */
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_OFF);
  assert_int_equal(rx.stats.bus_off, 1);
  e = error_frame(RANGING_CAN_ERR_CRTL, RANGING_CAN_ERR_CRTL_ACTIVE);
  ranging_can_rx_frame(&rx, &e, 0, NULL);  /* a controller report does not end a bus-off */
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_OFF);
  e = error_frame(RANGING_CAN_ERR_RESTARTED, 0);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_ACTIVE);
  assert_int_equal(rx.stats.restarts, 1);
  e = error_frame(RANGING_CAN_ERR_PROT | RANGING_CAN_ERR_ACK, 0);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  e = error_frame(RANGING_CAN_ERR_CRTL, RANGING_CAN_ERR_CRTL_RX_OVERFLOW);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  assert_int_equal(rx.stats.bus_errors, 1);
  assert_int_equal(rx.stats.controller_overflows, 1);
  assert_int_equal(rx.stats.error_frames, 8);
  assert_string_equal(ranging_can_bus_state_str(rx.bus_state), "active");
}

static void frames_after_a_missed_restart_report_end_bus_off(void **state)
{
  (void)state;
  struct ranging_can_raw e = error_frame(RANGING_CAN_ERR_BUSOFF, 0);
  ranging_can_rx_frame(&rx, &e, 0, NULL);
  assert_string_equal(ranging_can_bus_state_str(rx.bus_state), "bus-off");
  assert_int_equal(send(SELF, 9, 1000, 1, 1000, NULL), RANGING_CAN_RX_READING);
  assert_int_equal(rx.bus_state, RANGING_CAN_BUS_ACTIVE);
  assert_int_equal(rx.stats.restarts, 1);
}

static void bad_configurations_are_named(void **state)
{
  (void)state;
  const char *why;
  struct ranging_can_rx_config cfg = { .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = 64, .stale_us = 1 };
  assert_int_equal(ranging_can_rx_config_check(&cfg, &why), -1);
  assert_non_null(strstr(why, "self_id"));
  cfg.self_id = 1;
  cfg.stale_us = 0;
  assert_int_equal(ranging_can_rx_config_check(&cfg, &why), -1);
  assert_non_null(strstr(why, "stale_us"));
  cfg.stale_us = 1;
  cfg.layout.nb_nodes = 3;
  assert_int_equal(ranging_can_rx_config_check(&cfg, &why), -1);
  assert_non_null(strstr(why, "nb_nodes"));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup(readings_about_this_copter_fill_the_table, setup),
    cmocka_unit_test_setup(the_newest_distance_wins, setup),
    cmocka_unit_test_setup(a_stale_distance_is_never_fresh, setup),
    cmocka_unit_test_setup(sequence_gaps_duplicates_and_restarts_are_counted, setup),
    cmocka_unit_test_setup(invalid_frames_are_counted_by_reason, setup),
    cmocka_unit_test_setup(bus_off_and_restart_come_from_error_frames, setup),
    cmocka_unit_test_setup(frames_after_a_missed_restart_report_end_bus_off, setup),
    cmocka_unit_test(bad_configurations_are_named),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
