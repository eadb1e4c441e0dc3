#!/usr/bin/env bash
# Installs the Debian 12 packages kfw needs to build, test and run; does nothing when all are present.
set -euo pipefail
packages=(
  build-essential cmake make pkg-config clang-format-14 clang
  qt6-base-dev qt6-svg-dev libqcustomplot-dev
  libeigen3-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libmuparser-dev libginac-dev libfast-float-dev libhowardhinnant-date-dev
  libboost-math-dev libfftw3-dev libnlopt-dev parallel tzdata
  fonts-dejavu-core fontconfig poppler-utils
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root (or sudo) to apt-get install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp)
if ! { "${sudo_cmd[@]}" apt-get update -qq && \
       "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >"$log" 2>&1; then
  cat "$log" >&2
  echo "setup: apt-get failed (output above)" >&2
  exit 1
fi
rm -f "$log"
echo "setup: installed ${#missing[@]} packages"
