#!/bin/bash
# Submits a farm bake of a level: an array of N shard tasks (bake-array.sbatch) and the merge that waits for
# them (merge.sbatch). Prints the two job ids; with --wait, returns when the merge has ended, with its exit
# code. Extra arguments after N go to every task's `strata navmesh bake` (Recast settings).
#
#   tools/slurm/submit-bake.sh [--wait] LEVEL OUT_DIR N NAV.bin [navmesh bake options...]
#
# Slurm's own options (partition, account, time) come from the SBATCH_* variables, e.g.
# SBATCH_PARTITION=bake; STRATA names the strata executable every node runs.
set -euo pipefail

wait_for_merge=()
if [ "${1:-}" = "--wait" ]; then
  wait_for_merge=(--wait)
  shift
fi
if [ $# -lt 4 ]; then
  echo "usage: $0 [--wait] LEVEL OUT_DIR N NAV.bin [navmesh bake options...]" >&2
  exit 2
fi
# Absolute paths: the jobs run in OUT_DIR, on whichever node Slurm picks.
level=$(realpath -m -- "$1")
out_dir=$(realpath -m -- "$2")
shards=$3
navmesh=$(realpath -m -- "$4")
shift 4
if ! [[ "$shards" =~ ^[1-9][0-9]*$ ]]; then
  echo "submit-bake.sh: N must be a positive whole number, got '$shards'" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$out_dir"
array_job=$(sbatch --parsable --array=0-$((shards - 1)) --chdir="$out_dir" "$here/bake-array.sbatch" \
  "$level" "$out_dir" "$@")
array_job=${array_job%%;*}
echo "bake array: job $array_job ($shards tasks)"
echo "merge: waiting for job $array_job"
sbatch --parsable "${wait_for_merge[@]}" --dependency=afterok:"$array_job" --kill-on-invalid-dep=yes \
  --chdir="$out_dir" "$here/merge.sbatch" "$out_dir" "$shards" "$navmesh"
