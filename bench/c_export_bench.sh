#!/usr/bin/env bash
# Time per step of exported filters (docs/speed.md "Exported C"): kfw-cli export-c of cv1d (KF),
# range_bearing (EKF, UKF) and singer (Van Loan per dt), double and --float, each compiled with
# gcc -O2 and timed by bench/c_export_bench.c on the model's simulated data (best of 20 runs).
# Usage: bench/c_export_bench.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cli=${1:-$root/build}/app/kfw-cli
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() {  # preset sets channel inputs roles...: inputs and roles comma-separated ("-": none)
  local preset=$1 sets=$2 channel=$3 inputs=$4 roles=$5
  local nin=0 m
  [ "$inputs" != - ] && nin=$(tr ',' '\n' <<<"$inputs" | wc -l)
  m=$(tr ',' '\n' <<<"$roles" | wc -l)
  if [ -n "${DATA:-}" ]; then cp "$DATA" "$work/sim.csv"; else
    "$cli" simulate "$root/presets/$preset" $sets --set sim.duration=3600 --out "$work/sim.csv" >/dev/null
  fi
  python3 - "$work/sim.csv" "$work/data.csv" "$inputs" "$roles" <<'PY'
import csv, sys
src, dst = sys.argv[1], sys.argv[2]
cols = [c for c in (sys.argv[3].split(",") + sys.argv[4].split(",")) if c != "-"]
with open(src) as f, open(dst, "w") as o:
    for row in csv.DictReader(f):
        o.write(",".join([row["t"]] + [row[x] or "nan" for x in cols]) + "\n")
PY
  for prec in double float; do
    local flag="" real=double
    [ $prec = float ] && flag=--float && real=float
    "$cli" export-c "$root/presets/$preset" $sets $flag --out-dir "$work" --prefix f >/dev/null
    gcc -std=c99 -O2 -ffp-contract=off -D_POSIX_C_SOURCE=199309L -I"$work" -DEXPORT_H='"f.h"' \
      -DSTATE=f_state -DINIT=f_init -DPREDICT=f_predict -DUPDATE=f_update_$channel -DNZ=$m -DNIN=$nin \
      -DREAL=$real "$root/bench/c_export_bench.c" "$work/f.c" -lm -o "$work/bench"
    printf '%-16s %-18s %-6s ' "$preset" "$sets" "$prec"
    "$work/bench" "$work/data.csv" 20
  done
}
run models/cv1d.json "" position - z
run models/range_bearing.json "" radar - range,bearing
run models/range_bearing.json "--set filter=ukf" radar - range,bearing
run models/singer.json "" position - z
run models/cv_imm.json "" position - z
broad=$root/../shared/data/broad/10_undisturbed_slow_translation_A.csv
[ -f "$broad" ] && DATA=$broad run broad_imu.json "" angle gyro angle
