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
# binary through PXH_BINARY, so it runs instrumented with the same options (the asan preset
# of CMakePresets.json sets them for its build and its tests). Reports name file:line
# (symbolized through llvm-symbolizer or addr2line).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-$(nproc)}

# The asan presets: build-asan, RelWithDebInfo, -DPXH_SANITIZE=ON, the sanitizer options.
start=$(date +%s)
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
built=$(date +%s)
status=0
ctest --preset asan -j "$jobs" "$@" || status=$?
end=$(date +%s)
echo "sanitize.sh: build $((built - start)) s, tests $((end - built)) s; ctest exit status $status" >&2
exit $status
