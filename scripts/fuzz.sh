#!/usr/bin/env bash
# Fuzzes pxh's hostile-input parsers with libFuzzer (clang; ASan + UBSan, leaks detected).
#   scripts/fuzz.sh [SECONDS [TARGET...]]   SECONDS per target (default 60); targets default
#                                           to all: experiment thresholds csv image compare
# Configures build-fuzz with clang (-DPXH_FUZZ=ON: the project instrumented for coverage, ASan
# and UBSan), builds fuzz_TARGET, and runs each target for SECONDS (-max_total_time) from the
# committed seeds fuzz/corpus/TARGET/ plus what earlier runs kept (build-fuzz/corpus/TARGET/,
# not committed; new inputs go there). A crash, sanitizer report, leak, hang (> 10 s on one
# input) or out-of-memory (> 2 GB) stops that target and writes the input to
# build-fuzz/artifacts/TARGET/; the others still run, and the script exits 1 naming each one.
# Reproduce one: build-fuzz/fuzz_TARGET FILE (or, in the gcc build, pxh_fuzz_replay TARGET FILE).
# Once the bug is fixed, copy the input into fuzz/corpus/TARGET/ as a regression seed: the
# normal build's ctest entry fuzz_corpus_replay feeds every corpus file to its target.
# JOBS=N sets the build parallelism (default: the number of cores). FUZZ_ARGS adds libFuzzer
# options, e.g. FUZZ_ARGS="-fork=1 -ignore_ooms=1 -ignore_timeouts=1" to keep fuzzing past a
# known out-of-memory or hang (each one still leaves its input in artifacts/).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(experiment thresholds csv image compare)
jobs=${JOBS:-$(nproc)}
build=build-fuzz  # the fuzz preset's binaryDir

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (Debian: apt-get install clang)" >&2
  exit 2
fi

export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:print_stacktrace=1:print_summary=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:print_summary=1"

# The fuzz presets of CMakePresets.json: build-fuzz, clang, RelWithDebInfo, -DPXH_FUZZ=ON.
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs" --target "${targets[@]/#/fuzz_}"

failed=()
for t in "${targets[@]}"; do
  art="$build/artifacts/$t"
  mkdir -p "$build/corpus/$t" "$art"
  touch "$art/.start"  # inputs written after this are this run's findings
  dict=()
  [ -f "fuzz/$t.dict" ] && dict=("-dict=fuzz/$t.dict")
  echo "fuzz.sh: $t for ${seconds} s" >&2
  status=0
  "$build/fuzz_$t" "$build/corpus/$t" "fuzz/corpus/$t" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$art/" ${FUZZ_ARGS:-} 2>"$build/fuzz_$t.log" || status=$?
  grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)' "$build/fuzz_$t.log" >&2 || true
  # Each finding is one file named by its kind: crash-, leak-, timeout-, oom-, slow-unit-.
  # (The log can lack the message: the image loader silences stderr while a library reads.)
  found=$(find "$art" -type f -newer "$art/.start" ! -name .start | sort)
  if [ $status -ne 0 ] || [ -n "$found" ]; then
    failed+=("$t")
    echo "fuzz.sh: $t FOUND A PROBLEM (exit $status; log $build/fuzz_$t.log):" >&2
    grep -m1 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error' "$build/fuzz_$t.log" >&2 || true
    [ -n "$found" ] && echo "$found" >&2
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: findings in: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz.sh: no findings (${targets[*]}, ${seconds} s each)" >&2
