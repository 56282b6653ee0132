#!/usr/bin/env bash
# A private single-node Slurm runs a sharded pxh run for real: slurmctld and slurmd (Debian's,
# from apt; run.sh test installs them) in the foreground mode on 127.0.0.1 with the minimal
# tests/slurm/slurm.conf (copied with its state, spool and logs into a temporary folder), then
# examples/slurm/submit.sh submits a 4-task array of pxh run --shard and the afterok merge;
# the merged folder must equal the unsharded run cell by cell (timing columns aside).
#   tests/slurm/slurm_test.sh PXH_BINARY WORK_DIR
# Exit 0: passed; 1: failed (the reason on the last line); 77: cannot run here (not root),
# counted as skipped by ctest. Both daemons are stopped by their PIDs on every exit.
set -uo pipefail
pxh=$(realpath -e -- "${1:?usage: slurm_test.sh PXH_BINARY WORK_DIR}") || exit 1
work=${2:?usage: slurm_test.sh PXH_BINARY WORK_DIR}
src=$(cd "$(dirname "$0")/../.." && pwd)
t0=$(date +%s)

reason=""
fail() {
  reason="slurm_test: FAILED: $*"
  echo "$reason" >&2
  exit 1
}
for tool in slurmctld slurmd sbatch scontrol sinfo python3; do
  command -v "$tool" >/dev/null || fail "$tool is not installed (./run.sh test installs slurmctld, slurmd and slurm-client from apt)"
done
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm_test: SKIPPED: slurmd must run as root to start jobs (this is uid $(id -u))" >&2
  exit 77
fi

rm -rf "$work"
mkdir -p "$work"
dir=$(mktemp -d /tmp/pxh-slurm.XXXXXX) || fail "cannot create a temporary folder"
mkdir -p "$dir/state" "$dir/spool"
ctld_pid="" slurmd_pid=""
stop() {
  local rc=$?
  for p in $slurmd_pid $ctld_pid; do
    kill "$p" 2>/dev/null && wait "$p" 2>/dev/null
  done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for f in "$dir"/slurmctld.out "$dir"/slurmd.out "$work"/merged.slices/slurm-*.out; do
      [ -f "$f" ] && { echo "--- $f (last lines)" >&2; tail -n 15 "$f" >&2; }
    done
  fi
  rm -rf "$dir"
  [ -n "$reason" ] && echo "$reason" >&2  # again, last
  exit "$rc"
}
trap stop EXIT
trap 'exit 1' INT TERM

# Two free ports on 127.0.0.1 (the kernel's choice), the host's short name and CPUs.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])') || fail "no free ports"
host=$(hostname -s)
cpus=$(nproc)
sed -e "s|@DIR@|$dir|g" -e "s|@HOST@|$host|g" -e "s|@CPUS@|$cpus|g" \
  -e "s|@CTLD_PORT@|$ctld_port|g" -e "s|@SLURMD_PORT@|$slurmd_port|g" \
  "$src/tests/slurm/slurm.conf" >"$dir/slurm.conf" || fail "cannot write slurm.conf"
export SLURM_CONF="$dir/slurm.conf"

slurmctld -D -f "$SLURM_CONF" >"$dir/slurmctld.out" 2>&1 &
ctld_pid=$!
slurmd -D -f "$SLURM_CONF" >"$dir/slurmd.out" 2>&1 &
slurmd_pid=$!
up=""
for _ in $(seq 60); do
  kill -0 "$ctld_pid" 2>/dev/null || fail "slurmctld exited: $(tail -n 1 "$dir/slurmctld.out")"
  kill -0 "$slurmd_pid" 2>/dev/null || fail "slurmd exited: $(tail -n 1 "$dir/slurmd.out")"
  state=$(sinfo -h -n "$host" -o %T 2>/dev/null | head -n 1)
  case "$state" in idle*) up=yes; break ;; esac
  sleep 0.5
done
[ -n "$up" ] || fail "node $host not idle after 30 s (state '${state:-none}'): $(tail -n 1 "$dir/slurmd.out")"
echo "slurm_test: slurmctld (pid $ctld_pid, port $ctld_port) and slurmd (pid $slurmd_pid, port $slurmd_port) up on $host, $(slurmctld -V)"

exp="$src/results/experiments/default.toml"
opts=(--samples 8)
"$pxh" run "$exp" "${opts[@]}" --quiet --out "$work/full" >"$work/full.log" 2>&1 ||
  fail "the unsharded run failed: $(tail -n 1 "$work/full.log")"

# A refused submit creates nothing and says why in one line: a partition the cluster lacks,
# and an OUT that sbatch would read as a pattern.
bad=$(SBATCH_PARTITION=no_such_partition PXH="$pxh" "$src/examples/slurm/submit.sh" "$exp" "$work/bad" 2 2>&1) &&
  fail "submit.sh to a missing partition passed: $bad"
[ "$(wc -l <<<"$bad")" -eq 1 ] || fail "submit.sh's refusal is not one line: $bad"
grep -q "sbatch refused the job array: .*partition.*(SBATCH_PARTITION" <<<"$bad" ||
  fail "submit.sh does not explain sbatch's refusal: $bad"
[ ! -e "$work/bad.slices" ] && [ ! -e "$work/bad" ] || fail "a refused submit left $work/bad.slices behind"
echo "slurm_test: refused submit: $bad"
pct=$(PXH="$pxh" "$src/examples/slurm/submit.sh" "$exp" "$work/run-%j" 2 2>&1) && fail "OUT with % accepted: $pct"
grep -q "pattern" <<<"$pct" && [ ! -e "$work/run-%j.slices" ] || fail "OUT with %: $pct"

submitted=$(PXH="$pxh" "$src/examples/slurm/submit.sh" "$exp" "$work/merged" 4 "${opts[@]}" 2>&1) ||
  fail "submit.sh: $submitted"
echo "slurm_test: $submitted"
array=$(sed -n 's/^array \([0-9]*\) .*/\1/p' <<<"$submitted")
merge=$(sed -n 's/.*; merge \([0-9]*\) .*/\1/p' <<<"$submitted")
[ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in '$submitted'"

# Bounded wait for the merge job (its dependency waits for the array).
state=""
for _ in $(seq 480); do
  state=$(scontrol show job "$merge" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1)
  case "$state" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  sleep 0.5
done
tasks=$(scontrol show job "$array" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort | uniq -c | tr -s ' ' | tr '\n' ',')
[ "$state" = COMPLETED ] || fail "merge job $merge is ${state:-unknown} after 240 s (array $array tasks:${tasks})"
echo "slurm_test: array $array tasks:${tasks} merge job $merge COMPLETED"
n_slices=$(ls -d "$work"/merged.slices/shard-* 2>/dev/null | wc -l)
[ "$n_slices" -eq 4 ] || fail "$n_slices slices written, not 4"
log=$(ls "$work"/merged.slices/slurm-merge-*.out)
verified=$(grep "^verified: $work/merged/results.csv" "$log") || fail "the merge job printed no verification line of $work/merged ($log)"
"$pxh" report "$work/merged" --no-plots >"$work/report.log" 2>&1 ||
  fail "pxh report does not take the merged folder: $(tail -n 1 "$work/report.log")"
cmp_out=$(python3 "$src/scripts/compare_results.py" "$work/full/results.csv" "$work/merged/results.csv") ||
  fail "merged != unsharded: $cmp_out"
echo "slurm_test: $(head -n 1 <<<"$cmp_out" | sed 's/, timing columns skipped.*//'): $(tail -n 1 <<<"$cmp_out")"
echo "slurm_test: $verified"

# A requeued task whose slice is complete has nothing to do (exit 0, so afterok still holds);
# the merge takes complete slices only, not a killed task's .partial folder.
requeue=$(SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=4 PXH="$pxh" \
  bash "$src/examples/slurm/sweep.sbatch" "$exp" "$work/merged.slices" "${opts[@]}" 2>&1) ||
  fail "a requeued task of a complete slice failed: $requeue"
grep -q "complete already" <<<"$requeue" || fail "requeued task: $requeue"
mkdir "$work/merged.slices/shard-1.partial-999-abcdef01" || fail "cannot make a stray partial folder"
remerge=$(PXH="$pxh" bash "$src/examples/slurm/merge.sbatch" "$work/remerged" "$work/merged.slices" 2>&1) ||
  fail "merge.sbatch with a stray .partial folder: $remerge"
cmp_out=$(python3 "$src/scripts/compare_results.py" "$work/full/results.csv" "$work/remerged/results.csv") ||
  fail "re-merged != unsharded: $cmp_out"
echo "slurm_test: requeue of a complete slice skipped; a stray .partial folder left out of the merge"
echo "slurm_test: passed in $(($(date +%s) - t0)) s"
