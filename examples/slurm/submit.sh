#!/usr/bin/env bash
# Submits a pxh run as a Slurm job array of N slices and the merge that waits for them:
#   examples/slurm/submit.sh EXP OUT N [pxh run options...]
# The slices go to OUT.slices/shard-0 ... shard-(N-1) (with each task's Slurm log), the merged
# results folder to OUT. Prints the two job ids. sbatch's own environment variables choose
# the partition, time limit and CPUs (SBATCH_PARTITION, SBATCH_TIMELIMIT, ...; man sbatch);
# PXH names the pxh binary (default: pxh on PATH, else this repository's build/pxh).
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 EXP OUT N [pxh run options...]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
exp=$(realpath -e -- "$1") || { echo "$0: $1: no such experiment file" >&2; exit 2; }
out=$(realpath -m -- "$2")
n=$3
shift 3
case "$n" in '' | *[!0-9]* | 0) echo "$0: N must be a whole number >= 1, not '$n'" >&2; exit 2 ;; esac
if [ -e "$out" ] || [ -e "$out.slices" ]; then
  echo "$0: $out or $out.slices exists already: choose another OUT" >&2
  exit 2
fi
if [ -z "${PXH:-}" ]; then
  PXH=$(command -v pxh || true)
  [ -n "$PXH" ] || PXH="$here/../../build/pxh"
fi
PXH=$(realpath -e -- "$PXH") || { echo "$0: no pxh binary (set PXH)" >&2; exit 2; }
export PXH
slices="$out.slices"
mkdir -p "$slices"
array=$(sbatch --parsable --array="0-$((n - 1))" --output="$slices/slurm-%A_%a.out" \
  "$here/sweep.sbatch" "$exp" "$slices" "$@")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$slices/slurm-merge-%j.out" "$here/merge.sbatch" "$out" "$slices")
merge=${merge%%;*}
echo "array $array ($n tasks) -> $slices; merge $merge (afterok:$array) -> $out"
