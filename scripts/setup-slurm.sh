#!/usr/bin/env bash
# Installs Slurm and munge for the single-node Slurm test (tests/slurm/, docs/cluster.md): called
# by .ci/run and by that test, never by scripts/setup.sh. No service starts system-wide: a
# policy-rc.d refuses every start while apt-get runs, and the test starts its own daemons with a
# private configuration. Does nothing when the packages are present; exit 1 when they cannot be
# installed (no root, no network) — the test then skips and says why.
set -euo pipefail
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "setup-slurm: need root to apt-get install ${missing[*]}" >&2
  exit 1
fi
echo "setup-slurm: installing ${missing[*]}"
policy=/usr/sbin/policy-rc.d
had_policy=0
[ -e "$policy" ] && had_policy=1 && cp -p "$policy" "$policy.kfw-saved"
restore() {
  if [ "$had_policy" = 1 ]; then mv -f "$policy.kfw-saved" "$policy"; else rm -f "$policy"; fi
}
trap restore EXIT
printf '#!/bin/sh\nexit 101\n' >"$policy"
chmod 755 "$policy"
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp)
if ! { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
  >"$log" 2>&1; then
  cat "$log" >&2
  echo "setup-slurm: apt-get failed (output above)" >&2
  exit 1
fi
rm -f "$log"
echo "setup-slurm: installed ${#missing[@]} packages"
