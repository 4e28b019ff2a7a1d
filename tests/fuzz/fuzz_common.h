/*
 * Shared helpers of the libFuzzer harnesses (tests/fuzz/fuzz_*.c, one per parser of outside input; built with
 * clang -fsanitize=fuzzer,address,undefined by conf/Makefile.fuzz, run from the top of the tree).
 *
 * A harness finds a defect by crashing: a sanitizer report, or fuzz_require() failing on a property the parser
 * promises (e.g. a reading handed out once). Everything else an input does (an error message, a refusal) is fine.
 */
#ifndef FUZZ_COMMON_H
#define FUZZ_COMMON_H

#define _GNU_SOURCE
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** Stop with a message when a promised property does not hold (libFuzzer keeps the input as a crash). */
#define fuzz_require(cond) do { \
    if (!(cond)) { \
      fprintf(fuzz_report ? fuzz_report : stderr, "%s:%d: property does not hold: %s\n", __FILE__, __LINE__, #cond); \
      abort(); \
    } \
  } while (0)

/** Where fuzz_require reports: the real stderr (the code under test prints to /dev/null, fuzz_quiet_stdio). */
static FILE *fuzz_report;

/**
 * Send what the code under test prints on stdout/stderr to /dev/null (libraries that name a bad line on stderr
 * would print once per input). libFuzzer and the sanitizers keep writing to the real stderr.
 */
static inline void fuzz_quiet_stdio(void)
{
  fuzz_report = fdopen(dup(STDERR_FILENO), "w");
  if (fuzz_report != NULL) {
    setvbuf(fuzz_report, NULL, _IONBF, 0);
  }
  FILE *null = fopen("/dev/null", "w");
  if (fuzz_report == NULL || null == NULL) {
    perror("fuzz: /dev/null");
    exit(2);
  }
  stdout = null;
  stderr = null;
}

/** The input as a NUL-terminated string (stops at the first NUL byte); free() it. */
static inline char *fuzz_string(const uint8_t *data, size_t size)
{
  char *s = malloc(size + 1);
  if (s == NULL) {
    abort();
  }
  memcpy(s, data, size);
  s[size] = '\0';
  return s;
}

/**
 * The input as a file, for readers that only take a path: a memory file (one per process, rewritten for every
 * input), named /proc/self/fd/N.
 */
static inline const char *fuzz_file(const uint8_t *data, size_t size)
{
  static int fd = -1;
  static char path[64];
  if (fd < 0) {
    fd = memfd_create("fuzz-input", MFD_CLOEXEC);
    if (fd < 0) {
      perror("fuzz: memfd_create");
      abort();
    }
    snprintf(path, sizeof(path), "/proc/self/fd/%d", fd);
  }
  if (ftruncate(fd, 0) != 0 || (size > 0 && pwrite(fd, data, size, 0) != (ssize_t)size)) {
    perror("fuzz: writing the input file");
    abort();
  }
  return path;
}

/** Reads fixed-size fields off the front of an input; past its end every field reads as 0. */
struct fuzz_bytes {
  const uint8_t *p;
  size_t n;
};

static inline bool fuzz_more(const struct fuzz_bytes *b)
{
  return b->n > 0;
}

static inline uint64_t fuzz_take(struct fuzz_bytes *b, size_t bytes)
{
  uint64_t v = 0;
  for (size_t i = 0; i < bytes && b->n > 0; i++, b->p++, b->n--) {
    v |= (uint64_t)b->p[0] << (8 * i);
  }
  return v;
}

static inline uint8_t fuzz_u8(struct fuzz_bytes *b)
{
  return (uint8_t)fuzz_take(b, 1);
}

static inline uint16_t fuzz_u16(struct fuzz_bytes *b)
{
  return (uint16_t)fuzz_take(b, 2);
}

static inline uint32_t fuzz_u32(struct fuzz_bytes *b)
{
  return (uint32_t)fuzz_take(b, 4);
}

/** A double from 8 raw bytes: any bit pattern, NaN and infinities included. */
static inline double fuzz_double(struct fuzz_bytes *b)
{
  const uint64_t bits = fuzz_take(b, 8);
  double v;
  memcpy(&v, &bits, sizeof(v));
  return v;
}

#endif /* FUZZ_COMMON_H */
