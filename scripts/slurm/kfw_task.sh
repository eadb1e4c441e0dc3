#!/usr/bin/env bash
# One task of a kfw Slurm array (docs/cluster.md): task i of N runs shard i/N of a sweep, a Monte
# Carlo run (run --seeds) or a tuning (tune: start i of N) and writes OUTDIR/part_i.json, written
# atomically, so a part is either complete or absent. scripts/slurm_submit.sh submits it; by hand:
#
#   sbatch --array=1-16 scripts/slurm/kfw_task.sh OUTDIR 16 sweep PRESET --param Q=1:1e4:200 ...
#
# The contract (checked on every CI run by a fake sbatch, tests/cli/scale_slurm_cli_test.cpp):
# SLURM_ARRAY_TASK_ID is the shard index (array indices run from 1); N is given, not taken from
# SLURM_ARRAY_TASK_COUNT, so a resubmission of a few indices keeps the split; KFW_CLI is the
# kfw-cli to run (every node needs it, the preset and the data at the same paths); the task uses
# SLURM_CPUS_PER_TASK threads (--jobs) when Slurm sets it. A part carries no host names or times:
# re-running a task gives the same bytes.
#SBATCH --job-name=kfw
#SBATCH --output=kfw-%A_%a.log
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: sbatch --array=1-N $0 OUTDIR N sweep|run|tune ARGS..." >&2
  exit 2
fi
outdir=$1
shards=$2
command=$3
shift 3
: "${SLURM_ARRAY_TASK_ID:?run this through sbatch --array=1-N}"
case "$command" in
  sweep | run | tune) ;;
  *)
    echo "kfw_task: '$command' has no shards (sweep, run --seeds, tune)" >&2
    exit 2
    ;;
esac
kfw_cli=${KFW_CLI:-kfw-cli}
jobs=()
if [ -n "${SLURM_CPUS_PER_TASK:-}" ]; then jobs=(--jobs "$SLURM_CPUS_PER_TASK"); fi
mkdir -p "$outdir"
exec "$kfw_cli" "$command" "$@" "${jobs[@]}" \
  --shard "${SLURM_ARRAY_TASK_ID}/${shards}" \
  --out "$outdir/part_${SLURM_ARRAY_TASK_ID}.json"
