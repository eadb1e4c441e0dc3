#!/usr/bin/env bash
# Runs every libFuzzer harness of BUILD (default build-fuzz) for SECONDS each (default 60), starting
# from the committed seed corpus (tests/fuzz/corpus/NAME); new inputs go to BUILD/corpus/NAME,
# crashes to BUILD/artifacts/NAME/. Prints executions, coverage and features per harness; exits 1
# when a harness found anything.
set -uo pipefail
build=${1:-build-fuzz}
seconds=${2:-60}
here=$(cd "$(dirname "$0")" && pwd)
status=0
if [ "$seconds" -le 0 ]; then
  echo "fuzz: built in $build; FUZZ_SECONDS=$seconds, nothing run"
  exit 0
fi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for name in csv csv_mapped preset session set model_expr; do
  bin="$build/tests/fuzz/fuzz_$name"
  work="$build/corpus/$name"
  art="$build/artifacts/$name/"
  mkdir -p "$work" "$art"
  log="$build/fuzz_$name.log"
  "$bin" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$art" "$work" "$here/corpus/$name" >"$log" 2>&1
  rc=$?
  done_line=$(grep -E '^#[0-9]+ +DONE' "$log" | tail -1)
  execs=$(grep -E 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  echo "fuzz_$name: exit $rc, ${execs:-?} executions, ${done_line:-no DONE line (see $log)}"
  if [ $rc -ne 0 ]; then
    status=1
    grep -E 'kfw fuzz|ERROR: |SUMMARY' "$log" | head -5
  fi
done
exit $status
