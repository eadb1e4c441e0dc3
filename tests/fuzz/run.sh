#!/usr/bin/env bash
# Runs every libFuzzer harness of BUILD (default build-fuzz) for SECONDS each (default 60), JOBS at
# a time (default 1), starting from the committed seed corpus (tests/fuzz/corpus/NAME); new inputs
# go to BUILD/corpus/NAME, crashes to BUILD/artifacts/NAME/. Prints executions, coverage (cov:
# edges, ft: features) and the corpus size per harness; exits 1 when a harness found anything.
# FUZZ_HARNESSES="csv preset" runs a subset.
set -uo pipefail
build=${1:-build-fuzz}
seconds=${2:-60}
jobs=${3:-1}
here=$(cd "$(dirname "$0")" && pwd)
if [ "$seconds" -le 0 ]; then
  echo "fuzz: built in $build; FUZZ_SECONDS=$seconds, nothing run"
  exit 0
fi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export LSAN_OPTIONS=suppressions=$here/../lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
names=${FUZZ_HARNESSES:-csv csv_mapped preset session set model_expr model_file montecarlo_part sweep_part}

run_one() {
  local name=$1
  local bin="$build/tests/fuzz/fuzz_$name" work="$build/corpus/$name" art="$build/artifacts/$name/"
  mkdir -p "$work" "$art"
  local log="$build/fuzz_$name.log"
  "$bin" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$art" "$work" "$here/corpus/$name" >"$log" 2>&1
  echo $? >"$build/fuzz_$name.rc"
}

report() {
  local name=$1 log="$build/fuzz_$1.log"
  local rc execs last files
  rc=$(cat "$build/fuzz_$name.rc" 2>/dev/null || echo "?")
  execs=$(grep -m1 -E 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  # The last status line: "#N  DONE|REDUCE|NEW|pulse  cov: E ft: F corp: C/SIZE ... exec/s: R".
  last=$(grep -E '^#[0-9]+[[:space:]].*cov: ' "$log" | tail -1 |
    sed -E 's/^#[0-9]+[[:space:]]+[A-Za-z]+[[:space:]]+//; s/[[:space:]]+MS:.*//')
  files=$(find "$build/corpus/$name" -type f | wc -l)
  echo "fuzz_$name: exit $rc, ${execs:-?} executions, ${last:-no status line (see $log)}," \
    "$files files in $build/corpus/$name"
  if [ "$rc" != 0 ]; then
    grep -E 'kfw fuzz|ERROR: |SUMMARY|kfw: covariance' "$log" | head -5
    return 1
  fi
}

running=0
for name in $names; do
  run_one "$name" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait
status=0
for name in $names; do
  report "$name" || status=1
done
exit $status
