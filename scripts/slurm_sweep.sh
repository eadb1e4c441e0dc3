#!/usr/bin/env bash
# A sweep split over a Slurm array job: task i of N runs shard i/N of the grid and writes
# part_i.json; when every task is done, one merge gives the unsharded result exactly.
#
#   sbatch --array=1-16 scripts/slurm_sweep.sh 16 presets/helicopter.json out/ \
#          --param Q=1:1e4:200 --param R=0.01:100:200 --metric rmse
#   # after the array finished (or chain it: sbatch --dependency=afterok:JOBID ...):
#   build/app/kfw-cli merge out/part_*.json --out out/all.json
#
# Every task needs the same kfw-cli build, preset and dataset (a shared file system). The parts
# carry no timings or host names, so re-running a failed task (sbatch --array=7 ... 16 ...) and
# merging again gives the same result. N is given explicitly (not SLURM_ARRAY_TASK_COUNT) so that
# such a re-run keeps the split; array indices run from 1. --max-points applies to each shard.
#SBATCH --job-name=kfw-sweep
#SBATCH --cpus-per-task=4
#SBATCH --time=01:00:00
#SBATCH --output=kfw-sweep-%A_%a.log
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: sbatch --array=1-N $0 N PRESET OUTDIR SWEEP-OPTIONS..." >&2
  exit 2
fi
shards=$1
preset=$2
outdir=$3
shift 3
: "${SLURM_ARRAY_TASK_ID:?run this through sbatch --array=1-N}"
kfw_cli=${KFW_CLI:-build/app/kfw-cli}
mkdir -p "$outdir"
exec "$kfw_cli" sweep "$preset" "$@" \
  --shard "${SLURM_ARRAY_TASK_ID}/${shards}" \
  --out "$outdir/part_${SLURM_ARRAY_TASK_ID}.json"
