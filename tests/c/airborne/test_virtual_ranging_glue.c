/*
 * The virtual_ranging module's glue with a scripted ranging unit behind virtual_ranging_arch.h: distances are
 * clamped to [0, max], stored per peer (by aircraft id) and published as RANGING_DISTANCE with the module's
 * sender id; each copter has its own table. Exact.
 */
#include "test_helpers.h"
#include "modules/ranging/virtual_ranging.h"
#include "modules/ranging/virtual_ranging_arch.h"
#include "modules/core/abi.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"

static int periodic_calls;

bool virtual_ranging_arch_init(void)
{
  return true;
}

void virtual_ranging_arch_periodic(uint32_t now_us)
{
  periodic_calls++;
  virtual_ranging_report(7, 1.25f, now_us);
  virtual_ranging_report(9, 4.0f, now_us);      /* beyond the maximum: reads as the maximum */
  virtual_ranging_report(8, NAN, now_us);       /* no reading: nothing stored or sent */
}

void virtual_ranging_arch_event(uint32_t now_us)
{
  (void)now_us;
}

static uint8_t sent_peer[8];
static float sent_distance[8];
static int n_sent;

static void on_ranging(uint8_t sender_id, uint32_t stamp, uint16_t peer_id, float distance)
{
  assert_int_equal(sender_id, VIRTUAL_RANGING_ID);
  assert_int_equal(stamp, 2000000);
  sent_peer[n_sent] = peer_id;
  sent_distance[n_sent++] = distance;
}

static void distances_are_published_and_kept_per_peer(void **state)
{
  (void)state;
  static abi_event ev;
  pprz_vehicles_setup(2, NULL);
  sys_time_host_set(2.0);
  pprz_vehicle_select(1);
  AbiBindMsgRANGING_DISTANCE(ABI_BROADCAST, &ev, on_ranging);
  virtual_ranging_init();
  virtual_ranging_periodic();
  assert_int_equal(n_sent, 2);
  assert_int_equal(sent_peer[0], 7);
  assert_close(sent_distance[0], 1.25f, 0.0);
  assert_int_equal(sent_peer[1], 9);
  assert_close(sent_distance[1], VIRTUAL_RANGING_MAX_RANGE, 0.0);
  assert_non_null(ranging_table_find(virtual_ranging_table(), 7));
  assert_null(ranging_table_find(virtual_ranging_table(), 8));
  pprz_vehicle_select(0);   /* never initialised: not running, empty table */
  virtual_ranging_periodic();
  assert_int_equal(periodic_calls, 1);
  assert_null(ranging_table_find(virtual_ranging_table(), 7));
  pprz_vehicles_teardown();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(distances_are_published_and_kept_per_peer),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
