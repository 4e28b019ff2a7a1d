/*
 * The range recorder's pure part (range_recorder_rows.h): the rows of both files character for character (times,
 * NaN, peers, class names), the sensor names and codes, the files' paths and the 64-bit clock. Exact.
 */
#include "test_helpers.h"
#include "modules/range_recorder/range_recorder_rows.h"
#include "modules/wall_detector/wall_detector_reading.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

/** Assert the row formatted is `expected` and its length is returned. */
#define assert_row(len, row, expected) do { \
    assert_string_equal((row), (expected)); \
    assert_int_equal((len), strlen(expected)); \
  } while (0)

static size_t reading(char *row, uint64_t t_us, uint16_t vehicle, uint8_t sensor, uint16_t peer, float measured_m)
{
  const struct range_recorder_reading r = { t_us, vehicle, sensor, peer, measured_m };
  return range_recorder_reading_row(row, RANGE_RECORDER_ROW_LEN, &r);
}

static void sonar_rows_leave_the_peer_empty(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  size_t n = reading(row, 12350000u, 3, RANGE_RECORDER_SONAR_FRONT, RANGE_RECORDER_NO_PEER, 1.27f);
  assert_row(n, row, "12.350000,3,sonar_front,,1.27\n");
  n = reading(row, 1u, 3, RANGE_RECORDER_SONAR_RIGHT, 7, 0.2f);   /* a sonar's peer is never written */
  assert_row(n, row, "0.000001,3,sonar_right,,0.2\n");
  n = reading(row, 999999u, 64, RANGE_RECORDER_SONAR_BACK, RANGE_RECORDER_NO_PEER, 3.0f);
  assert_row(n, row, "0.999999,64,sonar_back,,3\n");
  n = reading(row, 60000000u, 1, RANGE_RECORDER_SONAR_LEFT, RANGE_RECORDER_NO_PEER, 0.61234f);
  assert_row(n, row, "60.000000,1,sonar_left,,0.61234\n");
  n = reading(row, 0u, 2, RANGE_RECORDER_SONAR_DOWN, RANGE_RECORDER_NO_PEER, 0.6f);
  assert_row(n, row, "0.000000,2,sonar_down,,0.6\n");
}

static void ranging_rows_name_the_peer(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  size_t n = reading(row, 12355120u, 3, RANGE_RECORDER_RANGING, 2, 1.44f);
  assert_row(n, row, "12.355120,3,ranging,2,1.44\n");
  n = reading(row, 5000000u, 300, RANGE_RECORDER_RANGING, 65535, 0.0f);   /* 16-bit ids, all of them */
  assert_row(n, row, "5.000000,300,ranging,65535,0\n");
}

static void no_reading_leaves_measured_empty(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  size_t n = reading(row, 2000000u, 3, RANGE_RECORDER_SONAR_DOWN, RANGE_RECORDER_NO_PEER, NAN);
  assert_row(n, row, "2.000000,3,sonar_down,,\n");
  n = reading(row, 2000000u, 3, RANGE_RECORDER_RANGING, 4, NAN);
  assert_row(n, row, "2.000000,3,ranging,4,\n");
  /* a glitch is data: written as it came */
  n = reading(row, 2000000u, 3, RANGE_RECORDER_SONAR_FRONT, 0, -0.5f);
  assert_row(n, row, "2.000000,3,sonar_front,,-0.5\n");
  n = reading(row, 2000000u, 3, RANGE_RECORDER_SONAR_FRONT, 0, INFINITY);
  assert_row(n, row, "2.000000,3,sonar_front,,inf\n");
}

static void times_are_exact_microseconds_beyond_32_bits(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  size_t n = reading(row, 4294967296u + 5u, 1, RANGE_RECORDER_SONAR_FRONT, 0, 1.0f);
  assert_row(n, row, "4294.967301,1,sonar_front,,1\n");
  n = reading(row, UINT64_MAX, 1, RANGE_RECORDER_SONAR_FRONT, 0, 1.0f);
  assert_row(n, row, "18446744073709.551615,1,sonar_front,,1\n");
}

/** measured: the fewest digits that read back as the same float, for 10^5 floats over the ranges of readings. */
static void measured_reads_back_as_the_same_float(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  uint32_t x = 12345u;
  for (int i = 0; i < 100000; i++) {
    const float value = (float)lcg_uniform(&x, -1.0, 60.0) * (i % 7 == 0 ? 1e-6f : 1.0f);
    reading(row, 0u, 1, RANGE_RECORDER_SONAR_FRONT, 0, value);
    char text[40];
    snprintf(text, sizeof(text), "%s", strrchr(row, ',') + 1);
    text[strcspn(text, "\n")] = '\0';
    if (strtof(text, NULL) != value) {
      print_error("%.9g written as %s", (double)value, text);
      fail();
    }
    /* the fewest significant digits that read back: no fewer digits do */
    char shortest[40] = "";
    for (int digits = 1; digits <= 9; digits++) {
      snprintf(shortest, sizeof(shortest), "%.*g", digits, (double)value);
      if (strtof(shortest, NULL) == value) {
        break;
      }
    }
    if (strcmp(text, shortest) != 0 || row[strlen(row) - 1] != '\n') {
      print_error("%.9g written as %s, shortest %s", (double)value, text, shortest);
      fail();
    }
  }
}

static void decision_rows_name_the_classes(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  struct range_recorder_decision d = { 12350000u, 3, 0, 1.27f, WALL_DETECTOR_WALL, 0.98f, WALL_DETECTOR_WALL };
  size_t n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_row(n, row, "12.350000,3,sonar_front,1.27,wall,0.98,wall\n");
  d = (struct range_recorder_decision) { 13000000u, 3, 3, 0.9f, WALL_DETECTOR_COPTER, 0.75f, WALL_DETECTOR_WALL };
  n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_row(n, row, "13.000000,3,sonar_left,0.9,copter,0.75,wall\n");
  d = (struct range_recorder_decision) { 1u, 12, 2, 3.0f, WALL_DETECTOR_NO_ECHO, 1.0f, WALL_DETECTOR_NO_ECHO };
  n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_row(n, row, "0.000001,12,sonar_back,3,none,1,none\n");
  d = (struct range_recorder_decision) { 1u, 12, 1, 1.5f, WALL_DETECTOR_UNKNOWN, 0.5f, 200 };
  n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_row(n, row, "0.000001,12,sonar_right,1.5,unknown,0.5,unknown\n");
  d.measured_m = NAN;
  d.confidence = NAN;
  n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_row(n, row, "0.000001,12,sonar_right,,unknown,,unknown\n");
}

static void what_is_no_row_gives_none(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  assert_int_equal(reading(row, 1u, 1, RANGE_RECORDER_SENSOR_NB, 0, 1.0f), 0);
  assert_string_equal(row, "");
  const struct range_recorder_decision down = { 1u, 1, RANGE_RECORDER_SONAR_DOWN, 0.6f, 1, 1.0f, 1 };
  assert_int_equal(range_recorder_decision_row(row, sizeof(row), &down), 0);
  assert_string_equal(row, "");
  /* a buffer too small: nothing, never a cut row */
  const struct range_recorder_reading r = { 12350000u, 3, RANGE_RECORDER_SONAR_FRONT, 0, 1.27f };
  char small[30];   /* "12.350000,3,sonar_front,,1.27\n" is 30 characters: no room for the NUL */
  assert_int_equal(range_recorder_reading_row(small, sizeof(small), &r), 0);
  assert_string_equal(small, "");
  char exact[31];
  assert_int_equal(range_recorder_reading_row(exact, sizeof(exact), &r), 30);
}

static void the_longest_rows_fit(void **state)
{
  (void)state;
  char row[RANGE_RECORDER_ROW_LEN];
  const struct range_recorder_reading r = { UINT64_MAX, 65535, RANGE_RECORDER_SONAR_RIGHT, 65535, -FLT_MAX };
  assert_true(range_recorder_reading_row(row, sizeof(row), &r) > 0);
  const struct range_recorder_decision d = { UINT64_MAX, 65535, 1, -FLT_MIN / 3.0f, 0, -FLT_MAX, 0 };
  const size_t n = range_recorder_decision_row(row, sizeof(row), &d);
  assert_true(n > 0 && n < RANGE_RECORDER_ROW_LEN);
  assert_string_equal(row + n - 1, "\n");
}

static void sensor_names_and_codes_match(void **state)
{
  (void)state;
  static const char *const names[RANGE_RECORDER_SENSOR_NB] = {
    "sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down", "ranging"
  };
  for (int i = 0; i < RANGE_RECORDER_SENSOR_NB; i++) {
    assert_string_equal(range_recorder_sensor_name((uint8_t)i), names[i]);
    assert_int_equal(range_recorder_sensor_code(names[i]), i);
  }
  assert_null(range_recorder_sensor_name(RANGE_RECORDER_SENSOR_NB));
  assert_null(range_recorder_sensor_name(255));
  assert_int_equal(range_recorder_sensor_code("sonar_up"), -1);
  assert_int_equal(range_recorder_sensor_code("Sonar_front"), -1);
  assert_int_equal(range_recorder_sensor_code(""), -1);
  assert_int_equal(range_recorder_sensor_code(NULL), -1);
  /* the telemetry's codes are sonar_array's indices */
  assert_int_equal(RANGE_RECORDER_SONAR_FRONT, 0);
  assert_int_equal(RANGE_RECORDER_SONAR_DOWN, 4);
  assert_int_equal(RANGE_RECORDER_RANGING, 5);
}

static void class_names_are_those_of_the_detections_log(void **state)
{
  (void)state;
  assert_string_equal(range_recorder_class_name(0), "unknown");
  assert_string_equal(range_recorder_class_name(1), "wall");
  assert_string_equal(range_recorder_class_name(2), "copter");
  assert_string_equal(range_recorder_class_name(3), "none");
  assert_string_equal(range_recorder_class_name(4), "unknown");
  assert_string_equal(range_recorder_class_name(255), "unknown");
}

static void paths_from_the_folder_or_the_pattern(void **state)
{
  (void)state;
  char path[64];
  assert_int_equal(range_recorder_file_path(path, sizeof(path), "/run/raw", "record", "/tmp/x.csv", 3),
                   strlen("/run/raw/record_3.csv"));
  assert_string_equal(path, "/run/raw/record_3.csv");
  assert_int_equal(range_recorder_file_path(path, sizeof(path), "out", "record_decisions", "", 12),
                   strlen("out/record_decisions_12.csv"));
  assert_string_equal(path, "out/record_decisions_12.csv");
  /* no folder: the pattern, each {ac_id} replaced */
  assert_int_equal(range_recorder_file_path(path, sizeof(path), NULL, "record", "/tmp/finken_record_{ac_id}.csv", 7),
                   strlen("/tmp/finken_record_7.csv"));
  assert_string_equal(path, "/tmp/finken_record_7.csv");
  range_recorder_file_path(path, sizeof(path), "", "record", "/d/{ac_id}/r{ac_id}.csv", 65535);
  assert_string_equal(path, "/d/65535/r65535.csv");
  range_recorder_file_path(path, sizeof(path), "", "record", "/d/{ac_id/r{}.csv", 4);
  assert_string_equal(path, "/d/{ac_id/r{}.csv");
  /* no file */
  assert_int_equal(range_recorder_file_path(path, sizeof(path), NULL, "record", "", 1), 0);
  assert_string_equal(path, "");
  assert_int_equal(range_recorder_file_path(path, sizeof(path), "", "record", NULL, 1), 0);
  /* too long: -1, an empty path */
  char small[20];
  assert_int_equal(range_recorder_file_path(small, sizeof(small), "/a/bc", "record", "", 1), 18);  /* 18 + NUL fits */
  assert_string_equal(small, "/a/bc/record_1.csv");
  assert_int_equal(range_recorder_file_path(small, sizeof(small), "/a/bcdef", "record", "", 1), -1);
  assert_string_equal(small, "");
  assert_int_equal(range_recorder_file_path(small, sizeof(small), NULL, "record", "/tmp/{ac_id}/1234567890.c", 1), 19);
  assert_string_equal(small, "/tmp/1/1234567890.c");
  assert_int_equal(range_recorder_file_path(small, sizeof(small), NULL, "record", "/tmp/{ac_id}/1234567890.c", 10), -1);
  assert_string_equal(small, "");
  assert_int_equal(range_recorder_file_path(small, 0, NULL, "record", "/tmp/x", 10), -1);
}

static void the_clock_runs_on_past_32_bits(void **state)
{
  (void)state;
  struct range_recorder_clock clock = { 0 };
  assert_true(range_recorder_clock_us(&clock, 4294967000u) == 4294967000u);   /* the first stamp as given */
  assert_true(range_recorder_clock_us(&clock, 4294966000u) == 4294966000u);   /* a slightly older one */
  assert_true(range_recorder_clock_us(&clock, 200u) == 4294967496u);          /* the stamps wrapped */
  assert_true(range_recorder_clock_us(&clock, 4294967100u) == 4294967100u);   /* older, from before the wrap */
  assert_true(range_recorder_clock_us(&clock, 300u) == 4294967596u);
  assert_true(clock.latest_us == 4294967596u);
  /* steps of 30 min (under the half range of 35.8 min): the clock follows over two more wraps, and back */
  uint64_t expected_us = clock.latest_us;
  uint32_t stamp = (uint32_t)expected_us;
  for (int i = 0; i < 5; i++) {
    stamp += 1800000000u;
    expected_us += 1800000000u;
    assert_true(range_recorder_clock_us(&clock, stamp) == expected_us);
  }
  assert_true(clock.latest_us == 4294967596u + 9000000000u);
  assert_true(range_recorder_clock_us(&clock, stamp - 1800000000u) == expected_us - 1800000000u);
  assert_true(clock.latest_us == expected_us);
}

static void a_stamp_before_the_clocks_zero_is_taken_as_given(void **state)
{
  (void)state;
  struct range_recorder_clock clock = { 0 };
  range_recorder_clock_us(&clock, 10u);
  /* 4294967290 is 16 us before 10 modulo 2^32, but no time is before 0 */
  assert_true(range_recorder_clock_us(&clock, 4294967290u) == 4294967290u);
  assert_true(clock.latest_us == 10u);
  assert_true(range_recorder_clock_us(&clock, 5u) == 5u);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(sonar_rows_leave_the_peer_empty),
    cmocka_unit_test(ranging_rows_name_the_peer),
    cmocka_unit_test(no_reading_leaves_measured_empty),
    cmocka_unit_test(times_are_exact_microseconds_beyond_32_bits),
    cmocka_unit_test(measured_reads_back_as_the_same_float),
    cmocka_unit_test(decision_rows_name_the_classes),
    cmocka_unit_test(what_is_no_row_gives_none),
    cmocka_unit_test(the_longest_rows_fit),
    cmocka_unit_test(sensor_names_and_codes_match),
    cmocka_unit_test(class_names_are_those_of_the_detections_log),
    cmocka_unit_test(paths_from_the_folder_or_the_pattern),
    cmocka_unit_test(the_clock_runs_on_past_32_bits),
    cmocka_unit_test(a_stamp_before_the_clocks_zero_is_taken_as_given),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
