#!/usr/bin/env bash
# Submits a pxh run as a Slurm job array of N slices and the merge that waits for them:
#   examples/slurm/submit.sh EXP OUT N [pxh run options...]
# The slices go to OUT.slices/shard-0 ... shard-(N-1) (with each task's Slurm log), the merged
# results folder to OUT. Prints the two job ids. sbatch's own environment variables choose
# the partition, time limit and CPUs (SBATCH_PARTITION, SBATCH_TIMELIMIT, ...; man sbatch);
# PXH names the pxh binary (default: pxh on PATH, else this repository's build/pxh).
# Nothing is created until Slurm has accepted the array: it is submitted held, OUT.slices is
# made, the merge is submitted, and the array released; if a step fails, what was submitted
# is cancelled and what was made removed, and sbatch's refusal is explained in one line.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 EXP OUT N [pxh run options...]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
exp=$(realpath -e -- "$1") || { echo "$0: $1: no such experiment file" >&2; exit 2; }
out=$(realpath -m -- "$2")
case "$out" in
  *%* | *\\*) echo "$0: OUT '$2' holds '%' or '\\', which sbatch reads as a pattern in --output: choose another OUT" >&2; exit 2 ;;
esac
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

# sbatch's refusal in one line: its first error line, and what it usually means.
explain() {
  local what=$1 err=$2 line hint=""
  line=$(printf '%s\n' "$err" | grep -m1 -i 'error' || printf '%s\n' "$err" | head -n1)
  line=${line#sbatch: }
  case "$err" in
    *"Unable to contact slurm controller"* | *"Connection refused"* | *"Zero Bytes were transmitted"*)
      hint="no Slurm controller answers: is slurmctld running, and SLURM_CONF the cluster's slurm.conf?" ;;
    *"Could not establish a configuration source"* | *"slurm.conf"*)
      hint="sbatch finds no slurm.conf: set SLURM_CONF to the cluster's" ;;
    *"Invalid partition"*) hint="SBATCH_PARTITION (or the default) names no partition: sinfo lists them" ;;
    *"Invalid account"* | *"Invalid qos"*) hint="set SBATCH_ACCOUNT / SBATCH_QOS to ones this user may use" ;;
    *"time limit"*) hint="SBATCH_TIMELIMIT exceeds the partition's limit: sinfo -o '%P %l' lists them" ;;
    *"MaxArraySize"* | *"array"*) hint="the cluster limits job arrays (MaxArraySize): use a smaller N" ;;
    *"node configuration"* | *"Requested node"*) hint="no node offers what SBATCH_* asks for (CPUs, memory)" ;;
  esac
  echo "$0: sbatch refused the $what: ${line:-no message}${hint:+ ($hint)}" >&2
}

err=$(mktemp) || exit 1
array=""
cleanup() {
  local rc=$?
  rm -f "$err"
  if [ "$rc" -ne 0 ] && [ -n "$array" ]; then
    scancel "$array" 2>/dev/null || true
    rmdir "$slices" 2>/dev/null || true
  fi
  exit "$rc"
}
trap cleanup EXIT
# Held: its tasks cannot start (and write into OUT.slices) before the merge is queued too.
if ! array=$(sbatch --parsable --hold --array="0-$((n - 1))" --output="$slices/slurm-%A_%a.out" \
  "$here/sweep.sbatch" "$exp" "$slices" "$@" 2>"$err"); then
  array=""
  explain "job array" "$(cat "$err")"
  exit 1
fi
array=${array%%;*}
mkdir -- "$slices" || { echo "$0: cannot create $slices" >&2; exit 1; }
if ! merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$slices/slurm-merge-%j.out" "$here/merge.sbatch" "$out" "$slices" 2>"$err"); then
  explain "merge job" "$(cat "$err")"
  exit 1
fi
merge=${merge%%;*}
scontrol release "$array" >/dev/null 2>"$err" || {
  scancel "$merge" 2>/dev/null || true
  echo "$0: scontrol release $array failed: $(head -n1 "$err")" >&2
  exit 1
}
echo "array $array ($n tasks) -> $slices; merge $merge (afterok:$array) -> $out"
