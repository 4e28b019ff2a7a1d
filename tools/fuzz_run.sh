#!/bin/sh
# Run one libFuzzer harness (tests/fuzz/fuzz_*.c, built by conf/Makefile.fuzz), with one line of report.
#
#   tools/fuzz_run.sh fuzz BIN SECONDS CORPUS_DIR ARTIFACT_DIR LOG [SEED...]
#       fuzz for SECONDS, starting from CORPUS_DIR (created; "" for a temporary one, removed afterwards) with the
#       SEED files copied in; new inputs that reach new code are added to it. A crash (sanitizer report, failed
#       property, leak, timeout, out of memory) leaves its input in ARTIFACT_DIR: the report names it, shows the
#       end of the log and says how to replay it and keep it as a regression.
#   tools/fuzz_run.sh replay BIN LOG [FILE...]
#       run each FILE through the harness once (the regression inputs of tests/fuzz/regressions/<harness>/).
#
# The whole output of the harness goes to LOG. Exit status: 0, or 1 on a crash.
set -u
mode=$1 bin=$2
name=$(basename "$bin")
# per input: 10 s at most; memory: libFuzzer's default limit (2 GB), a larger allocation is a crash too
options="-timeout=10 -rss_limit_mb=2048"
export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

fail() {   # $1: what happened, $2: the log
  echo "  $name: FAILED ($1); end of $2:" >&2
  grep -v '^#[0-9]' "$2" | tail -n 40 | sed 's/^/    /' >&2
}

case "$mode" in
  replay)
    log=$3
    shift 3
    mkdir -p "$(dirname "$log")"
    if [ $# -eq 0 ]; then
      echo "  $name: no regression inputs"
      exit 0
    fi
    if "$bin" $options "$@" >"$log" 2>&1; then
      echo "  $name: $# regression input(s) replayed: ok"
      exit 0
    fi
    fail "a regression input crashes it again" "$log"
    exit 1 ;;
  fuzz)
    seconds=$3 corpus=$4 artifacts=$5 log=$6
    shift 6
    temporary=""
    if [ -z "$corpus" ]; then
      corpus=$(mktemp -d "${TMPDIR:-/tmp}/$name.corpus.XXXXXX")
      temporary=$corpus
      trap 'rm -rf "$temporary"' EXIT
    fi
    mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
    for seed in "$@"; do   # named by their path: seeds of two folders may share a name
      cp "$seed" "$corpus/$(printf '%s' "$seed" | tr / _)"
    done
    before=$(ls "$artifacts" | wc -l)
    "$bin" $options -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" \
      >"$log" 2>&1
    rc=$?
    crash=$(ls -t "$artifacts" | head -n 1)
    if [ $rc -ne 0 ] || [ "$(ls "$artifacts" | wc -l)" -ne "$before" ]; then
      fail "exit status $rc" "$log"
      if [ -n "$crash" ] && [ "$(ls "$artifacts" | wc -l)" -ne "$before" ]; then
        echo "  reproducer: $artifacts/$crash" >&2
        echo "  replay it:  $bin $artifacts/$crash" >&2
        echo "  fix the parser, then keep it: cp $artifacts/$crash tests/fuzz/regressions/$name/" >&2
      fi
      exit 1
    fi
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    reach=$(grep '^#[0-9]' "$log" | tail -n 1 | sed -n 's/.*\(cov: [0-9]*\).*\(corp: [^ ]*\).*/\1, \2/p')
    echo "  $name: ${runs:-?} inputs in $seconds s (${reach:-no coverage line}): ok"
    exit 0 ;;
  *)
    echo "usage: $0 fuzz BIN SECONDS CORPUS_DIR ARTIFACT_DIR LOG [SEED...] | replay BIN LOG [FILE...]" >&2
    exit 2 ;;
esac
