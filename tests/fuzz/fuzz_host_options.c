/*
 * libFuzzer harness: the NPS host's command line, sim/nps_host_options.c (getopt_long, whole and decimal
 * numbers with their ranges). Input: the arguments, separated by newlines. Properties: a command line that is
 * taken gives values within the documented ranges.
 */
#include "fuzz_common.h"

#include <getopt.h>
#include <math.h>

#include "nps_host_options.h"
#include "nps_host_threads.h"

/** Arguments at most (more are left out). */
#define ARGS_MAX 32

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char *text = fuzz_string(data, size);
  char *argv[ARGS_MAX + 2] = { "nps_host" };
  int argc = 1;
  for (char *arg = text, *next; arg != NULL && argc <= ARGS_MAX; arg = next) {
    next = strchr(arg, '\n');
    if (next != NULL) {
      *next++ = '\0';
    }
    argv[argc++] = arg;
  }
  argv[argc] = NULL;
  optind = 0;   /* glibc: start afresh (a new command line) */
  struct nps_host_options opt;
  const int rc = nps_host_parse_options(argc, argv, &opt);
  fuzz_require(rc >= -1 && rc <= 1);
  if (rc == 0) {
    fuzz_require(opt.vehicles >= 1 && opt.vehicles <= 4096 && opt.threads <= NPS_HOST_THREADS_MAX);
    fuzz_require(opt.duration_s >= 0.0 && opt.duration_s <= 1e9 && opt.out_dir != NULL);
    fuzz_require(opt.pose_rate_hz == 0.0 || (opt.pose_rate_hz >= 1e-3 && opt.pose_rate_hz <= 1e6));
  }
  free(text);
  return 0;
}
