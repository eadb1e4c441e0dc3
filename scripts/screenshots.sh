#!/usr/bin/env bash
# Regenerates screenshots/ from the built binaries (no display needed): every plot of every preset
# made by `kfw --export`, the variants the README shows, and one window per preset.
# Usage: scripts/screenshots.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
kfw="$build/app/kfw"
[ -x "$kfw" ] || { echo "screenshots: $kfw not built (make build)" >&2; exit 1; }
export QT_QPA_PLATFORM=offscreen
export QT_LOGGING_RULES="qt.qpa.*=false"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
out=screenshots
rm -rf "$out"
mkdir -p "$out"
for preset in presets/*.json; do
  name=$(basename "$preset" .json)
  "$kfw" --export "$out" "$preset" >/dev/null
  # (the offscreen platform's propagateSizeHints notice is noise; any other output is shown)
  if ! "$kfw" --screenshot "$out/window_$name.png" "$preset" >/dev/null 2>"$out/.log"; then
    cat "$out/.log" >&2
    exit 1
  fi
  grep -v propagateSizeHints "$out/.log" >&2 || true
  rm -f "$out/.log"
done
# The window and presentation mode on a 1280 × 720 projector and a 1366 × 768 laptop, the screen
# itself set to that size (the offscreen platform's screen configuration).
for size in 1280x720 1366x768; do
  for preset in helicopter radome models/cv_imm; do
    stem=$(echo "$preset" | tr / _)
    for mode in window present; do
      flag=()
      [ "$mode" = present ] && flag=(--present)
      QT_QPA_PLATFORM="offscreen:configfile=tests/gui/screens/$size.json" \
        "$kfw" --screenshot "$out/${mode}_${size}_$stem.png" "${flag[@]}" --size "$size" \
        "presets/$preset.json" >/dev/null 2>&1
    done
  done
done
# Variants shown in the README beside the defaults.
"$kfw" --export "$out/radome_B_Kp045" presets/radome.json --set sim.amplitude=0.08 --set Kp=0.45 >/dev/null
"$kfw" --export "$out/radome_B_Kp0" presets/radome.json --set sim.amplitude=0.08 --set Kp=0 >/dev/null
"$kfw" --export "$out/ballbeam_detection_off" presets/ballbeam.json --set detection=0 >/dev/null
"$kfw" --export "$out/underwater_AS" presets/underwater.json --set scheme=AS >/dev/null
# The variants differ in their scenario plots; their consistency plots add nothing to show.
rm -f "$out"/*/*_consistency_*.png
find "$out" -name '*.png' | sort
