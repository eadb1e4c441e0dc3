#!/usr/bin/env bash
# Runs gtest binaries the way `make sanitize` does (docs/hardening.md "Sanitizers"): each binary in JOBS shards
# at once (GTEST_TOTAL_SHARDS), one process per shard instead of ctest's one process per test.
# Under AddressSanitizer a process takes 2-3 s to start (its 200 MB binary registers every
# instrumented global), which over ~450 tests was most of the run.
# Usage: tests/run_sharded.sh BUILD_DIR JOBS EXCLUDE_FILTER BINARY...
#   EXCLUDE_FILTER: a gtest pattern list (A.*:B.C) left out, or "" for none.
# Exit status: 0 when every shard passed; each failing shard's output is printed.
set -uo pipefail
build=$1 jobs=$2 exclude=$3
shift 3
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
args=()
[ -n "$exclude" ] && args=("--gtest_filter=-$exclude")
status=0
for bin in "$@"; do
  start=$(date +%s)
  pids=()
  for ((i = 0; i < jobs; i++)); do
    (cd "$build/tests" && GTEST_TOTAL_SHARDS=$jobs GTEST_SHARD_INDEX=$i QT_QPA_PLATFORM=offscreen \
      "./$bin" "${args[@]}" > "$logs/$bin.$i" 2>&1) &
    pids+=($!)
  done
  for ((i = 0; i < jobs; i++)); do
    if ! wait "${pids[$i]}"; then
      status=1
      echo "=== $bin shard $i/$jobs FAILED; its output:"
      cat "$logs/$bin.$i"
    fi
  done
  passed=$(cat "$logs/$bin".* | grep -c '^\[       OK \]')
  failed=$(cat "$logs/$bin".* | grep -c '^\[  FAILED  \] .*ms)$')
  skipped=$(cat "$logs/$bin".* | grep -c '^\[  SKIPPED \] .*ms)$')
  reports=$(cat "$logs/$bin".* | grep -c -E '^(==[0-9]+==ERROR|.*runtime error:)')
  echo "$bin: $passed passed, $failed failed, $skipped skipped, $reports sanitizer reports," \
    "$(($(date +%s) - start)) s"
  [ "$reports" -eq 0 ] || status=1
done
exit $status
