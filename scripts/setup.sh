#!/usr/bin/env bash
# Installs the Debian 12 packages kcwarp needs. Idempotent: packages already present are left
# alone, so a second run costs a second.
#   bash scripts/setup.sh         everything: build, run, tests, benchmarks, fuzzers (scripts/build.sh, test.sh)
#   bash scripts/setup.sh --run   only what builds and runs kcwarp and kcwarp-cli (scripts/run.sh)
set -euo pipefail
run_packages=(
  build-essential cmake pkg-config ninja-build
  libeigen3-dev libopencv-dev libcgal-dev libsuitesparse-dev
  libpng-dev   # PNG read/write without loading OpenCV's ~140 codec libraries (app/src/png_codec.h)
  libjpeg-dev  # strict JPEG reading: truncated or corrupt data refused (app/src/jpeg_codec.h)
  libopenblas0-pthread   # fast BLAS under CHOLMOD's supernodal factorization (~4x on kernel matrices)
  nlohmann-json3-dev libcli11-dev
  libglfw3-dev libimgui-dev libgl-dev
)
test_packages=(
  libgtest-dev libbenchmark-dev
  libglpk-dev coinor-libclp-dev   # reference LP / QP solvers used only by the tests
  xvfb xauth mesa-utils xdotool imagemagick   # the GUI's end-to-end tests under a virtual display
  clang libclang-rt-14-dev   # libFuzzer + sanitizers for the fuzz targets (scripts/fuzz.sh)
  lld   # links the sanitized executables in a fifth of GNU ld's time (scripts/sanitized_build.sh)
)
packages=("${run_packages[@]}")
case "${1:-}" in
  --run) ;;
  "") packages+=("${test_packages[@]}") ;;
  *) echo "usage: bash scripts/setup.sh [--run]" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
