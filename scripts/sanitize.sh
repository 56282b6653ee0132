#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (gcc).
#   scripts/sanitize.sh                  configure build-asan (-DPXH_SANITIZE=ON, RelWithDebInfo),
#                                        build everything, run the whole ctest suite
#   scripts/sanitize.sh -R 'Csv|fuzz'    extra arguments go to ctest (here: a subset)
# JOBS=N sets the build and ctest parallelism (default: the number of cores).
# Any ASan report (out-of-bounds, use-after-free, ...), any UB (overflow, bad shift, float to
# int overflow, misaligned or null access; -fno-sanitize-recover) and any leak fails the test
# that caused it: leak detection stays on, and only leaks inside third-party libraries, each
# listed with its reason in tests/sanitizers/lsan.supp, are suppressed. Tests run the pxh
# binary through PXH_BINARY, so it runs instrumented with the same options (they are
# exported here). Reports name file:line (symbolized through llvm-symbolizer or addr2line).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=${JOBS:-$(nproc)}
build=build-asan

export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=0:print_stacktrace=1:check_initialization_order=1:strict_init_order=1:detect_invalid_pointer_pairs=0:print_summary=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:print_summary=1"

start=$(date +%s)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPXH_SANITIZE=ON -Wno-dev >/dev/null
cmake --build "$build" -j "$jobs"
built=$(date +%s)
status=0
ctest --test-dir "$build" --output-on-failure -j "$jobs" "$@" || status=$?
end=$(date +%s)
echo "sanitize.sh: build $((built - start)) s, tests $((end - built)) s; ctest exit status $status" >&2
exit $status
