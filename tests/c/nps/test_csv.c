/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file test_csv.c
 * The log number formatting gives printf's text byte for byte: "%.9g" for every value, "%.4f" for every
 * value that is not an exact decimal tie; random values (fixed seed) over every decade the logs use, powers
 * of ten and their neighbours (the decimal exponent guess), and hand cases. Exact. Spooled rows reach their
 * files only when flushed, in the order written, per file.
 */
#include "test_helpers.h"
#include "nps_csv.h"

#include <gsl/gsl_rng.h>
#include <string.h>

/** Random values per decade. */
#define CSV_TEST_PER_DECADE 20000

static void check_g9(double x)
{
  char fast[NPS_CSV_NUMBER_LEN], ref[NPS_CSV_NUMBER_LEN];
  const int n = nps_csv_g9(fast, x);
  snprintf(ref, sizeof(ref), "%.9g", x);
  if (strcmp(fast, ref) != 0 || n != (int)strlen(ref)) {
    print_error("%.17g: nps_csv_g9 \"%s\", printf \"%s\"\n", x, fast, ref);
    fail();
  }
}

static void g9_is_printf_for_every_magnitude(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 9);
  for (int decade = -16; decade <= 33; decade++) {
    const double p = pow(10.0, decade);
    check_g9(p);
    check_g9(nextafter(p, 0.0));
    check_g9(nextafter(p, INFINITY));
    check_g9(-p);
    for (int i = 0; i < CSV_TEST_PER_DECADE; i++) {
      const double x = p * (1.0 + 9.0 * gsl_rng_uniform(rng));
      check_g9(i % 2 ? x : -x);
    }
  }
  const double hand[] = { 0.0, -0.0, 0.5, 1.0, 0.1, 123456789.5, 999999999.7, 1e-5, 0.0001, 1e300, INFINITY, NAN };
  for (size_t i = 0; i < sizeof(hand) / sizeof(hand[0]); i++) {
    check_g9(hand[i]);
  }
  gsl_rng_free(rng);
}

static void fixed4_is_printf(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 10);
  char fast[NPS_CSV_NUMBER_LEN], ref[NPS_CSV_NUMBER_LEN];
  for (int i = 0; i < 200000; i++) {
    const double x = (gsl_rng_uniform(rng) - 0.5) * pow(10.0, (double)(i % 8));
    nps_csv_fixed4(fast, x);
    snprintf(ref, sizeof(ref), "%.4f", x);
    assert_string_equal(fast, ref);
  }
  for (int i = 0; i < 200000; i++) {   /* up to 1e20, where x * 1e4 is no longer exact; exact ties are common there */
    const double x = (gsl_rng_uniform(rng) - 0.5) * pow(10.0, (double)(11 + i % 10));
    nps_csv_fixed4(fast, x);
    snprintf(ref, sizeof(ref), "%.4f", x);
    assert_string_equal(fast, ref);
  }
  const double ties[] = { 0.03125, 0.09375, -0.03125, 2.5e-5 * 3, 142056428594.51475 };   /* k / 32: exact ties */
  for (size_t i = 0; i < sizeof(ties) / sizeof(ties[0]); i++) {
    nps_csv_fixed4(fast, ties[i]);
    snprintf(ref, sizeof(ref), "%.4f", ties[i]);
    assert_string_equal(fast, ref);
  }
  gsl_rng_free(rng);
}

static void fixed4_of_a_huge_number_fits_its_buffer(void **state)
{
  (void)state;
  const double huge[] = { 1e20, -1e100, 1.7976931348623157e308, -INFINITY, NAN };
  const char *expected[] = { "1e+20", "-1e+100", "1.79769313e+308", "-inf", "nan" };
  for (size_t i = 0; i < sizeof(huge) / sizeof(huge[0]); i++) {
    char out[NPS_CSV_NUMBER_LEN + 16];
    memset(out, 'X', sizeof(out));
    const int n = nps_csv_fixed4(out, huge[i]);
    assert_true(n < NPS_CSV_NUMBER_LEN);
    assert_string_equal(out, expected[i]);
    assert_int_equal(out[NPS_CSV_NUMBER_LEN], 'X');   /* nothing written past the number's room */
  }
}

/** The text of a temporary file, closed. */
static void read_back(FILE *f, char *text, size_t len)
{
  rewind(f);
  const size_t n = fread(text, 1, len - 1, f);
  text[n] = '\0';
  fclose(f);
}

static void spooled_rows_reach_their_files_on_flush(void **state)
{
  (void)state;
  FILE *a = tmpfile(), *b = tmpfile();
  assert_non_null(a);
  assert_non_null(b);
  nps_csv_write(a, "direct\n", 7);   /* no spool: straight to the file */
  struct nps_csv_spool spool = { .n_files = 0 };
  nps_csv_spool_use(&spool);
  nps_csv_write(a, "a1\n", 3);
  nps_csv_write(b, "b1\n", 3);
  char big[10000];
  memset(big, 'x', sizeof(big));     /* past the first allocation */
  nps_csv_write(a, big, sizeof(big));
  nps_csv_write(a, "a2\n", 3);
  nps_csv_spool_use(NULL);
  fflush(a);
  assert_int_equal(ftell(a), 7);      /* nothing spooled is in the file yet */
  nps_csv_write(a, "later\n", 6);
  assert_int_equal(nps_csv_spool_flush(&spool), 0);
  assert_int_equal(nps_csv_spool_flush(&spool), 0);   /* emptied: nothing twice */
  nps_csv_spool_free(&spool);
  char text[12000];
  read_back(b, text, sizeof(text));
  assert_string_equal(text, "b1\n");
  read_back(a, text, sizeof(text));
  assert_int_equal(strlen(text), 7 + 6 + 3 + sizeof(big) + 3);
  assert_memory_equal(text, "direct\nlater\na1\n", 16);
  assert_string_equal(text + 16 + sizeof(big), "a2\n");
}

static void a_spool_with_too_many_files_reports_the_lost_rows(void **state)
{
  (void)state;
  FILE *f[NPS_CSV_SPOOL_FILES + 1];
  struct nps_csv_spool spool = { .n_files = 0 };
  nps_csv_spool_use(&spool);
  for (int i = 0; i <= NPS_CSV_SPOOL_FILES; i++) {
    f[i] = tmpfile();
    assert_non_null(f[i]);
    nps_csv_write(f[i], "row\n", 4);
  }
  nps_csv_spool_use(NULL);
  assert_int_equal(nps_csv_spool_flush(&spool), -1);
  assert_int_equal(nps_csv_spool_flush(&spool), 0);   /* reported once */
  nps_csv_spool_free(&spool);
  for (int i = 0; i <= NPS_CSV_SPOOL_FILES; i++) {
    char text[8];
    read_back(f[i], text, sizeof(text));
    assert_string_equal(text, i < NPS_CSV_SPOOL_FILES ? "row\n" : "");
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(g9_is_printf_for_every_magnitude),
    cmocka_unit_test(fixed4_is_printf),
    cmocka_unit_test(fixed4_of_a_huge_number_fits_its_buffer),
    cmocka_unit_test(spooled_rows_reach_their_files_on_flush),
    cmocka_unit_test(a_spool_with_too_many_files_reports_the_lost_rows),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
