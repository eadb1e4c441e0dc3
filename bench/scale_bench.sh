#!/usr/bin/env bash
# Issue 33's figures (docs/speed.md "Long logs", "Memory per row", "Cores"): not a test.
#   bench/scale_bench.sh [BUILD] [WORKDIR]
# Makes 1 M and 3.6 M rows of the helicopter model file (an hour of its world block simulated,
# tiled with a continuing clock), 10 M rows of the BROAD log (../shared/data, tiled), and runs:
#   kfw-cli run with and without --out (every default column), peak RSS by /usr/bin/time;
#   bytes per row of run and --out at 2, 9 and 20 states (helicopter, 9-state diagonal, 20-state
#   diagonal, bench/make_diagonal_model.py) from the RSS at 1 M and 2 M rows;
#   kfw --bench-latency on the 10 M-row BROAD file (open + draw, slider → replot p95, RSS);
#   run --seeds, sweep and tune with --jobs 1 and every core.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$here/build}" && pwd)
work=${2:-${TMPDIR:-/tmp}/kfw_scale_bench}
cli=$build/app/kfw-cli
gui=$build/app/kfw
mkdir -p "$work"
cd "$work"
t() { /usr/bin/time -f "%e s, %M KiB peak RSS" "$@" 2>&1 >/dev/null | tail -1; }

tile() {  # tile SRC ROWS DT OUT: SRC's rows repeated with a continuing clock
  python3 - "$@" <<'PY'
import sys
src, rows, dt, out = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
lines = open(src).read().splitlines()
body = [l.split(",", 1)[1] for l in lines[1:]]
with open(out, "w") as f:
    f.write(lines[0] + "\n")
    buf = []
    for k in range(rows):
        buf.append(repr(round(k * dt, 10)) + "," + body[k % len(body)] + "\n")
        if len(buf) == 100000:
            f.write("".join(buf)); buf = []
    f.write("".join(buf))
PY
}

[ -f heli_1h.csv ] || "$cli" simulate "$here/presets/helicopter.json" --set sim.duration=3600 --out heli_1h.csv >/dev/null
for n in 1000000 2000000 3600000; do
  [ -f "heli_$n.csv" ] || tile heli_1h.csv "$n" 0.02 "heli_$n.csv"
done
echo "== helicopter model file (2 states), kfw-cli run"
for n in 1000000 3600000; do
  echo "$n rows, no --out:  $(t "$cli" run "$here/presets/helicopter.json" --data "heli_$n.csv")"
  echo "$n rows, --out:     $(t "$cli" run "$here/presets/helicopter.json" --data "heli_$n.csv" --out est.csv)"
  rm -f est.csv
done

echo "== bytes per row (RSS at 2 M minus 1 M rows, / 1 M)"
for s in 9 20; do
  [ -f "diag$s.json" ] || python3 "$here/bench/make_diagonal_model.py" "$s" >"diag$s.json"
  for n in 1000000 2000000; do
    [ -f "diag${s}_$n.csv" ] || "$cli" simulate "diag$s.json" --set sim.duration=$((n / 10)) --out "diag${s}_$n.csv" >/dev/null 2>&1 ||
      python3 - "$s" "$n" "diag${s}_$n.csv" <<'PY'
import sys, random
s, n, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
random.seed(1)
with open(out, "w") as f:
    f.write("t," + ",".join(f"z{i}" for i in range(s)) + "\n")
    for k in range(n):
        f.write(f"{k * 0.01:.2f}," + ",".join(f"{random.gauss(0, 1):.6f}" for _ in range(s)) + "\n")
PY
  done
done
rss() { /usr/bin/time -f "%M" "$@" 2>&1 >/dev/null | tail -1; }
for m in helicopter:heli "diag9.json:diag9" "diag20.json:diag20"; do
  preset=${m%%:*}; stem=${m#*:}
  [ "$preset" = helicopter ] && preset=$here/presets/helicopter.json
  r1=$(rss "$cli" run "$preset" --data "${stem}_1000000.csv"); r2=$(rss "$cli" run "$preset" --data "${stem}_2000000.csv")
  o1=$(rss "$cli" run "$preset" --data "${stem}_1000000.csv" --out est.csv); o2=$(rss "$cli" run "$preset" --data "${stem}_2000000.csv" --out est.csv)
  echo "$stem: run $(( (r2 - r1) * 1024 / 1000000 )) B/row, run --out $(( (o2 - o1) * 1024 / 1000000 )) B/row"
  rm -f est.csv
done

if [ -d "$here/../shared/data/broad" ]; then
  echo "== kfw on 10 M rows of the BROAD log (broad_imu)"
  [ -f broad_10m.csv ] || tile "$here/../shared/data/broad/10_undisturbed_slow_translation_A.csv" 10000000 0.0035 broad_10m.csv
  QT_QPA_PLATFORM=offscreen /usr/bin/time -f "%e s, %M KiB peak RSS" "$gui" "$here/presets/broad_imu.json" --data broad_10m.csv --bench-latency --changes 20 2>&1 | tail -4
fi

echo "== cores: --jobs 1 and every core (outputs compared byte for byte)"
h=$here/presets/helicopter.json
for j in 1 0; do
  opt=(); [ $j -gt 0 ] && opt=(--jobs $j)
  echo "run --seeds 1..800, jobs ${j/0/all}: $(t "$cli" run "$h" --seeds 1..800 --out "mc$j.json" "${opt[@]}")"
  echo "sweep 40x40,        jobs ${j/0/all}: $(t "$cli" sweep "$h" --param Q=1:1e4:40 --param R=0.01:100:40 --metric rmse --out "sw$j.json" "${opt[@]}")"
done
cmp mc1.json mc0.json && cmp sw1.json sw0.json && echo "outputs identical"
