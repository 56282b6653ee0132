#!/usr/bin/env bash
# One-command set-up: installs missing Debian packages, builds build/pxh (Release), then
#   ./run.sh            runs the default experiment and prints a summary
#   ./run.sh test       runs the whole test suite through ctest
#   ./run.sh build      only builds
# PXH_WERROR=ON in the environment: warnings are errors (for CI: .ci/run).
set -euo pipefail
cd "$(dirname "$0")"

# glslang-tools, spirv-cross: HLSL plug-ins (docs/guide/plugin-shaders.md, "HLSL and WGSL").
PACKAGES=(
  g++ cmake ninja-build pkg-config git zlib1g-dev libpng-dev
  libembree-dev libopenimageio-dev openimageio-tools libeigen3-dev libgtest-dev
  libosmesa6-dev libegl-dev libegl-mesa0 libgl1-mesa-dri python3-glad fonts-dejavu-core python3-matplotlib libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libtbb-dev
  clang-format
  glslang-tools spirv-cross
)
# ./run.sh test only: Slurm for the slurm_array test (a private single-node cluster).
TEST_PACKAGES=(slurmctld slurmd slurm-client)

install_missing() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "run.sh: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# WGSL plug-ins: naga (npm naga-wasm, the exact version and hash in tools/naga/package-lock.json)
# run by node, installed into tools/naga/node_modules (git-ignored). Debian's nodejs and npm
# only where no node or npm is installed (a NodeSource nodejs carries its own npm).
install_naga() {
  command -v node >/dev/null || install_missing nodejs
  command -v npm >/dev/null || install_missing npm
  local want have
  want=$(cd tools/naga && node -p "require('./package.json').dependencies['naga-wasm']")
  have=$(cd tools/naga && node -p "require('./node_modules/naga-wasm/package.json').version" 2>/dev/null || true)
  [ "$have" = "$want" ] && return 0
  echo "run.sh: installing naga-wasm $want (npm ci in tools/naga)" >&2
  (cd tools/naga && npm ci --no-audit --no-fund --ignore-scripts --loglevel=error)
}

# The release presets of CMakePresets.json (build/, Ninja, Release).
build() {
  cmake --preset release -DPXH_WERROR="${PXH_WERROR:-OFF}" >/dev/null
  cmake --build --preset release -j "$(nproc)"
}

mode="${1:-run}"
case "$mode" in
  run|test|build) ;;
  -h|--help) sed -n 2,6p "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "run.sh: unknown mode '$mode' (run | test | build)" >&2; exit 2 ;;
esac

if [ "$mode" = test ]; then install_missing "${PACKAGES[@]}" "${TEST_PACKAGES[@]}"
else install_missing "${PACKAGES[@]}"; fi
install_naga
build
case "$mode" in
  run) ./build/pxh run results/experiments/default.toml ;;
  test) ctest --preset release -j "$(nproc)" ;;
esac
