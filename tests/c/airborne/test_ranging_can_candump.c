/* candump -l log lines (modules/ranging/ranging_can_candump.h): every frame kind can-utils writes, and
 * malformed lines rejected with a reason. */
#include "test_helpers.h"
#include "modules/ranging/ranging_can_candump.h"

#include <string.h>

static struct ranging_can_candump_line parse_ok(const char *line)
{
  struct ranging_can_candump_line l;
  const char *why = NULL;
  const int rc = ranging_can_candump_parse(line, &l, &why);
  if (rc != 1) {
    print_error("'%s': %s\n", line, why ? why : "(blank)");
  }
  assert_int_equal(rc, 1);
  return l;
}

static void a_classical_frame(void **state)
{
  (void)state;
  const struct ranging_can_candump_line l = parse_ok("(1700000000.123456) can0 123#DEADBEEF\n");
  assert_true(l.time_us == 1700000000123456ULL);
  assert_string_equal(l.ifname, "can0");
  assert_int_equal(l.frame.can_id, 0x123);
  assert_int_equal(l.frame.len, 4);
  assert_false(l.frame.fd);
  const uint8_t data[8] = { 0xDE, 0xAD, 0xBE, 0xEF, 0, 0, 0, 0 };
  assert_memory_equal(l.frame.data, data, 8);
}

static void extended_empty_dotted_and_flagged_frames(void **state)
{
  (void)state;
  struct ranging_can_candump_line l = parse_ok("(0.000001) vcan0 1F334455#11.22.33");
  assert_int_equal(l.frame.can_id, 0x1F334455U | RANGING_CAN_ID_EFF_FLAG);
  assert_int_equal(l.frame.len, 3);
  assert_int_equal(l.frame.data[2], 0x33);
  assert_true(l.time_us == 1);
  l = parse_ok("(1.5) can1 7FF#");
  assert_int_equal(l.frame.len, 0);
  assert_true(l.time_us == 1500000);
  l = parse_ok("(1.123456789) can0 300#0102030405060708_C T\r\n");  /* ns decimals, DLC suffix, direction */
  assert_true(l.time_us == 1123456);
  assert_int_equal(l.frame.len, 8);
}

static void remote_fd_and_error_frames(void **state)
{
  (void)state;
  struct ranging_can_candump_line l = parse_ok("(1.000000) can0 303#R");
  assert_int_equal(l.frame.can_id, 0x303 | RANGING_CAN_ID_RTR_FLAG);
  assert_int_equal(l.frame.len, 0);
  l = parse_ok("(1.000000) can0 303#R8");
  assert_int_equal(l.frame.len, 8);
  l = parse_ok("(1.000000) can0 303##100112233445566778899AABB");
  assert_true(l.frame.fd);
  assert_int_equal(l.frame.fd_flags, 1);
  assert_int_equal(l.frame.len, 12);
  assert_int_equal(l.frame.data[11], 0xBB);
  l = parse_ok("(1.000000) can0 20000040#0000000000000000");
  assert_int_equal(l.frame.can_id, RANGING_CAN_ID_ERR_FLAG | 0x40);
  assert_int_equal(l.frame.len, 8);
}

static void blank_lines_are_skipped(void **state)
{
  (void)state;
  struct ranging_can_candump_line l;
  const char *why;
  assert_int_equal(ranging_can_candump_parse("", &l, &why), 0);
  assert_int_equal(ranging_can_candump_parse("   \n", &l, &why), 0);
}

static void malformed_lines_say_what_was_expected(void **state)
{
  (void)state;
  static const struct {
    const char *line;
    const char *why_contains;
  } bad[] = {
    { "1700000000.123456 can0 123#00", "'('" },
    { "(1700000000) can0 123#00", "decimals" },
    { "(1700000000.) can0 123#00", "decimals" },
    { "(17x.1) can0 123#00", "seconds" },
    { "(1.1)can0 123#00", "space" },
    { "(1.1) can0", "interface name and a frame" },
    { "(1.1) averyveryverylongname0 123#00", "15 characters" },
    { "(1.1) can0 12#00", "3 (standard) or 8" },
    { "(1.1) can0 1234#00", "3 (standard) or 8" },
    { "(1.1) can0 123456789#00", "3 (standard) or 8" },
    { "(1.1) can0 123:00", "'#'" },
    { "(1.1) can0 123#0", "pairs of hex digits" },
    { "(1.1) can0 123#0G", "pairs of hex digits" },
    { "(1.1) can0 123#001122334455667788", "more than 8 bytes" },
    { "(1.1) can0 123##X00", "flags" },
    { "(1.1) can0 123#001122_9", "needs 8 data bytes" },
    { "(1.1) can0 123#0011223344556677_3", "DLC from 9" },
    { "(1.1) can0 123#00 trailing words", "unexpected text" },
    { "(1.1) can0 E0000001#00", "error frame id" },
    { "(1.1) can0 7FFFFFFF#00", "error frame id" },
    { "(1.1) can0 20000040##100", "cannot be a CAN FD" },
    { "(1.1) can0 30C98085#R", "cannot be a remote request" },  /* found by tests/fuzz/fuzz_candump.c */
    { "(1.1) can0 123#_123:456#00", "needs 8 data bytes" },  /* a CAN XL line */
  };
  for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
    struct ranging_can_candump_line l;
    memset(&l, 0x77, sizeof(l));
    const char *why = NULL;
    const int rc = ranging_can_candump_parse(bad[i].line, &l, &why);
    if (rc != -1 || why == NULL || strstr(why, bad[i].why_contains) == NULL) {
      print_error("'%s': rc %d, why '%s', expected '%s'\n", bad[i].line, rc, why ? why : "", bad[i].why_contains);
      fail();
    }
    assert_int_equal(l.frame.len, 0x77);  /* untouched */
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(a_classical_frame),
    cmocka_unit_test(extended_empty_dotted_and_flagged_frames),
    cmocka_unit_test(remote_fd_and_error_frames),
    cmocka_unit_test(blank_lines_are_skipped),
    cmocka_unit_test(malformed_lines_say_what_was_expected),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
