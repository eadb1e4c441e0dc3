#!/usr/bin/env bash
# A private single-node Slurm for tests and trials (docs/cluster.md): `start DIR` writes a
# slurm.conf under DIR (private ports, SlurmUser root, no cgroups, no accounting, one node with
# CPUs=2 at 127.0.0.1), starts munged (if none runs) and slurmctld + slurmd, and waits until the
# node is idle; it prints `export SLURM_CONF=DIR/slurm.conf`. `stop DIR` stops what start started.
# Needs root and scripts/setup-slurm.sh's packages. On failure it prints the failing daemon's last
# log line and exits 1.
set -euo pipefail
cmd=${1:-}
dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ]; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi
dir=$(mkdir -p "$dir" && cd "$dir" && pwd)
conf=$dir/slurm.conf

stop() {
  for d in slurmd slurmctld munged; do
    if [ -f "$dir/$d.pid" ]; then
      kill "$(cat "$dir/$d.pid")" 2>/dev/null || true
      rm -f "$dir/$d.pid"
    fi
  done
}

last_line() {  # the failing daemon's last log line
  tail -n 1 "$dir/$1.log" 2>/dev/null || echo "(no log)"
}

start() {
  for b in munged slurmctld slurmd sinfo; do
    command -v "$b" >/dev/null || { echo "single_node: $b not installed (scripts/setup-slurm.sh)" >&2; exit 1; }
  done
  [ "$(id -u)" -eq 0 ] || { echo "single_node: needs root" >&2; exit 1; }
  mkdir -p "$dir/state" "$dir/spool"
  local base=$(( 20000 + ($$ % 20000) ))
  cat >"$conf" <<CONF
ClusterName=kfwtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
InactiveLimit=0
KillWait=5
MinJobAge=300
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  if ! pgrep -x munged >/dev/null; then
    mkdir -p /run/munge
    chown munge:munge /run/munge
    chmod 0755 /run/munge
    if ! runuser -u munge -- /usr/sbin/munged >"$dir/munged.log" 2>&1; then
      echo "single_node: munged failed: $(last_line munged)" >&2
      exit 1
    fi
    pgrep -x munged >"$dir/munged.pid" || true
  fi
  export SLURM_CONF=$conf
  if ! slurmctld -i -f "$conf" >>"$dir/slurmctld.log" 2>&1; then
    echo "single_node: slurmctld failed: $(last_line slurmctld)" >&2
    stop; exit 1
  fi
  if ! slurmd -f "$conf" >>"$dir/slurmd.log" 2>&1; then
    echo "single_node: slurmd failed: $(last_line slurmd)" >&2
    stop; exit 1
  fi
  for _ in $(seq 1 60); do
    if sinfo -h -o %T 2>/dev/null | grep -qx idle; then
      echo "export SLURM_CONF=$conf"
      return 0
    fi
    sleep 0.5
  done
  echo "single_node: the node did not become idle in 30 s: $(last_line slurmctld) / $(last_line slurmd)" >&2
  stop
  exit 1
}

case "$cmd" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: $0 start|stop DIR" >&2; exit 2 ;;
esac
