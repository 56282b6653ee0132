#!/usr/bin/env bash
# LDR-FLIP speed (issue 63): pxh's implementation against the authors' CPU implementation on the
# same 512 x 512 pair (tests/metrics/flip_pairs.h, bench512), one thread each, the median of
# the repeats, both in this one run.
#   scripts/flip_bench.sh [FLIP_CHECKOUT] [--repeats N]
# FLIP_CHECKOUT: a checkout of https://github.com/NVlabs/flip (its src/cpp/FLIP.h; measured with
# commit 1eb247cabcf2862c2c8207ab15314304394132b9). Without it only pxh is timed. The authors'
# header is compiled, outside the source tree (in the build folder), into pxh's driver
# scripts/flip_bench_authors.cpp at -O2 and at -O3 (-march=x86-64-v2 as pxh, no OpenMP).
# Needs a release build (build/pxh_flip_bench: cmake --build --preset release).
set -euo pipefail
cd "$(dirname "$0")/.."
flip_dir="" repeats=9
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    -h|--help) sed -n 2,10p "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) flip_dir="$1"; shift ;;
  esac
done
bin=build/pxh_flip_bench
[ -x "$bin" ] || { echo "flip_bench.sh: $bin not built (cmake --build --preset release)" >&2; exit 2; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')"
"$bin" --repeats "$repeats" --threads 1
if [ -n "$flip_dir" ]; then
  header="$flip_dir/src/cpp/FLIP.h"
  [ -f "$header" ] || { echo "flip_bench.sh: $header not found" >&2; exit 2; }
  echo "authors: $(git -C "$flip_dir" rev-parse HEAD 2>/dev/null || echo "commit unknown")"
  # Their code is faster at -O2 than at -O3 with g++ 12: both are timed, the faster is theirs.
  for opt in -O2 -O3; do
    out=build/flip_bench_authors$opt
    "${CXX:-g++}" -std=c++17 "$opt" -DNDEBUG -march=x86-64-v2 -w -I"$flip_dir/src/cpp" \
      -Itests/metrics scripts/flip_bench_authors.cpp -o "$out"
    echo "($opt) $("$out" --repeats "$repeats")"
  done
fi
