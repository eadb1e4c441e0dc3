#!/usr/bin/env bash
# A sweep, a Monte Carlo run or a tuning as a Slurm job array, then one merge (docs/cluster.md).
#
#   scripts/slurm_submit.sh OUTDIR N sweep PRESET --param Q=1:1e4:200 --metric rmse
#   scripts/slurm_submit.sh OUTDIR N run PRESET --seeds 1..8000
#   scripts/slurm_submit.sh OUTDIR N tune PRESET --data 'logs/*.csv'
#   scripts/slurm_submit.sh --resume OUTDIR   # resubmit only the missing or failed shards
#
# Task i writes OUTDIR/part_i.json (scripts/slurm/kfw_task.sh); a merge job that waits for the
# array (afterok) writes OUTDIR/sweep.json, OUTDIR/montecarlo.json + metrics.json, or
# OUTDIR/tuned.json + tune.json, and its summary to OUTDIR/merge.log. If a task fails the merge
# job is cancelled; `--resume OUTDIR` asks `kfw-cli merge --resume` which parts are missing or
# invalid and resubmits exactly those indices (all N when none is complete), then the merge.
# SBATCH_ARGS (e.g. "--partition=short --cpus-per-task=8 --time=01:00:00") is passed to both
# sbatch calls; KFW_CLI names the kfw-cli (default: this checkout's build/app/kfw-cli).
# Prints the job ids: "array JOBID" and "merge JOBID".
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
task=$here/slurm/kfw_task.sh
usage() {
  echo "usage: $0 OUTDIR N sweep|run|tune ARGS...   or   $0 --resume OUTDIR" >&2
  exit 2
}
[ $# -ge 1 ] || usage
if [ "$1" = --resume ]; then
  [ $# -eq 2 ] || usage
  outdir=$(cd "$2" && pwd)
  [ -f "$outdir/kfw_job.args" ] || { echo "slurm_submit: $outdir/kfw_job.args: not a folder this script submitted" >&2; exit 2; }
  mapfile -d '' -t saved <"$outdir/kfw_job.args"
  kfw_cli=${saved[0]}
  shards=${saved[1]}
  args=("${saved[@]:2}")
  set +e
  spec=$("$kfw_cli" merge --resume "$outdir")
  rc=$?
  set -e
  if [ $rc -eq 2 ]; then
    spec="1-$shards"  # no complete part: the whole array again
  elif [ $rc -ne 0 ]; then
    exit $rc
  fi
else
  [ $# -ge 4 ] || usage
  mkdir -p "$1"
  outdir=$(cd "$1" && pwd)
  shards=$2
  shift 2
  case "$shards" in '' | *[!0-9]*) echo "slurm_submit: N: expected a count, found '$shards'" >&2; exit 2 ;; esac
  [ "$shards" -ge 1 ] || usage
  kfw_cli=${KFW_CLI:-$here/../build/app/kfw-cli}
  kfw_cli=$(cd "$(dirname "$kfw_cli")" && pwd)/$(basename "$kfw_cli")
  [ -x "$kfw_cli" ] || { echo "slurm_submit: $kfw_cli: no kfw-cli (make build, or set KFW_CLI)" >&2; exit 2; }
  args=("$@")
  case "${args[0]}" in
    sweep | run | tune) ;;
    *) echo "slurm_submit: '${args[0]}' has no shards (sweep, run --seeds, tune)" >&2; exit 2 ;;
  esac
  printf '%s\0' "$kfw_cli" "$shards" "${args[@]}" >"$outdir/kfw_job.args"
  spec="1-$shards"
fi
case "${args[0]}" in
  sweep) merge_out=(--out "$outdir/sweep.json") ;;
  run) merge_out=(--out "$outdir/montecarlo.json" --metrics "$outdir/metrics.json") ;;
  tune) merge_out=(--out "$outdir/tuned.json" --metrics "$outdir/tune.json") ;;
  *) echo "slurm_submit: '${args[0]}' has no shards (sweep, run --seeds, tune)" >&2; exit 2 ;;
esac
read -r -a extra <<<"${SBATCH_ARGS:-}"
merge_cmd=$(printf '%q ' "$kfw_cli" merge "${merge_out[@]}")"$(printf '%q' "$outdir")/part_*.json"
dependency=()
if [ -n "$spec" ]; then
  array=$(KFW_CLI=$kfw_cli sbatch --parsable --export=ALL,KFW_CLI="$kfw_cli" "${extra[@]}" \
    --array="$spec" --output="$outdir/task_%a.log" "$task" "$outdir" "$shards" "${args[@]}")
  array=${array%%;*}
  echo "array $array ($spec of 1-$shards)"
  dependency=(--dependency="afterok:$array" --kill-on-invalid-dep=yes)
fi
merge=$(sbatch --parsable "${extra[@]}" "${dependency[@]}" --job-name=kfw-merge \
  --output="$outdir/merge.log" --wrap="$merge_cmd")
echo "merge ${merge%%;*}"
