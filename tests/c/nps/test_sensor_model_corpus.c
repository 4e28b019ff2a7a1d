/*
 * The shared corpus of sensor models (tests/data/models, errors listed in expected.txt): the C loaders accept
 * every file of good/ and refuse every file of bad/ with the error the list gives, at the line it gives.
 * tests/python/test_model_corpus.py loads the same files through the Python tools and expects the same.
 * A .xml file is a model file (nps_sensor_model_load); a .txt file holds the one-line form
 * (nps_sensor_model_from_text_for_log of its bytes, named by its path). The simulator's entry point,
 * nps_sensor_model_from_define, must agree on every file it can be given (a C string: no NUL byte).
 */
#include "test_helpers.h"

#include <dirent.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "nps_sensor_model.h"

#define CORPUS "tests/data/models"
#define MAX_FILES 128
#define NAME_LEN 128

static int compare_names(const void *a, const void *b)
{
  return strcmp(a, b);
}

/** The sorted names of the files of a corpus folder; returns how many. */
static size_t list_files(const char *dir, char names[][NAME_LEN])
{
  DIR *d = opendir(dir);
  assert_non_null(d);
  size_t n = 0;
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d)) {
    if (e->d_name[0] != '.') {
      const size_t len = strlen(e->d_name);
      assert_true(n < MAX_FILES && len < NAME_LEN);
      memcpy(names[n++], e->d_name, len + 1);
    }
  }
  closedir(d);
  qsort(names, n, NAME_LEN, compare_names);
  return n;
}

/** The bytes of a file, NUL-terminated (*len excludes the terminator). */
static char *read_bytes(const char *path, size_t *len)
{
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  char *buf = malloc(1 << 16);
  assert_non_null(buf);
  *len = fread(buf, 1, (1 << 16) - 1, f);
  assert_true(feof(f));
  buf[*len] = '\0';
  fclose(f);
  return buf;
}

static bool is_text_form(const char *path)
{
  const char *dot = strrchr(path, '.');
  return dot != NULL && strcmp(dot, ".txt") == 0;
}

/** Load a corpus file as the tools do; 0, or -1 with the error in err. Either way the result is checked whole. */
static int load(const char *path, char *err, size_t err_len)
{
  struct nps_sensor_model *m = (struct nps_sensor_model *)1;
  size_t len;
  char *bytes = read_bytes(path, &len);
  int rc = is_text_form(path) ? nps_sensor_model_from_text_for_log(bytes, len, path, 0, NULL, &m, err, err_len)
           : nps_sensor_model_load(path, &m, err, err_len);
  assert_true(rc == 0 ? m != NULL : m == NULL);   /* a model, or none */
  nps_sensor_model_free(m);
  /* the simulator's entry point: a model file's path, or the one-line text itself */
  if (strlen(bytes) == len) {
    char define_err[NPS_SENSOR_MODEL_ERR_LEN] = "";
    struct nps_sensor_model *d;
    const int define_rc = nps_sensor_model_from_define(is_text_form(path) ? bytes : path, path, &d, define_err,
                          sizeof(define_err));
    nps_sensor_model_free(d);
    assert_int_equal(define_rc, rc);
    assert_string_equal(define_err, rc == 0 ? "" : err);
  }
  free(bytes);
  return rc;
}

static void every_good_model_loads(void **state)
{
  (void)state;
  static char names[MAX_FILES][NAME_LEN];
  size_t n = list_files(CORPUS "/good", names);
  assert_true(n >= 4);
  for (size_t i = 0; i < n; i++) {
    char path[256], err[NPS_SENSOR_MODEL_ERR_LEN] = "";
    snprintf(path, sizeof(path), CORPUS "/good/%s", names[i]);
    if (load(path, err, sizeof(err)) != 0) {
      print_error("%s was refused: %s\n", path, err);
      fail();
    }
  }
}

struct expected {
  char file[NAME_LEN];
  long line;
  char reason[NPS_SENSOR_MODEL_ERR_LEN];
};

/** The entries of expected.txt ("file line reason", '#' comments); returns how many. */
static size_t read_expected(struct expected *e)
{
  FILE *f = fopen(CORPUS "/expected.txt", "r");
  assert_non_null(f);
  char row[1024];
  size_t n = 0;
  while (fgets(row, sizeof(row), f) != NULL) {
    row[strcspn(row, "\n")] = '\0';
    if (row[0] == '#' || row[0] == '\0') {
      continue;
    }
    int reason_at = 0;
    assert_true(n < MAX_FILES);
    assert_int_equal(sscanf(row, "%127s %ld %n", e[n].file, &e[n].line, &reason_at), 2);
    snprintf(e[n].reason, sizeof(e[n].reason), "%s", row + reason_at);
    assert_true(e[n].reason[0] != '\0');
    n++;
  }
  fclose(f);
  return n;
}

static void every_bad_model_is_refused_with_its_error(void **state)
{
  (void)state;
  static char names[MAX_FILES][NAME_LEN];
  static struct expected expected[MAX_FILES];
  size_t n = list_files(CORPUS "/bad", names), n_expected = read_expected(expected);
  assert_int_equal(n, n_expected);   /* one entry per file (the names are compared below) */
  for (size_t i = 0; i < n_expected; i++) {
    const struct expected *e = &expected[i];
    char path[256], where[300], err[NPS_SENSOR_MODEL_ERR_LEN] = "";
    snprintf(path, sizeof(path), CORPUS "/bad/%.127s", e->file);
    assert_non_null(bsearch(e->file, names, n, NAME_LEN, compare_names));
    snprintf(where, sizeof(where), "%s:%ld: ", path, e->line);
    if (load(path, err, sizeof(err)) != -1 || strncmp(err, where, strlen(where)) != 0 ||
        strstr(err + strlen(where), e->reason) == NULL) {
      print_error("%s\n  error    '%s'\n  expected '%s...%s'\n", path, err, where, e->reason);
      fail();
    }
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(every_good_model_loads),
    cmocka_unit_test(every_bad_model_is_refused_with_its_error),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
