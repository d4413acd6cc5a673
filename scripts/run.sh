#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root) with only the packages kcwarp runs with
# (scripts/setup.sh --run), builds only the GUI and the command line (kcwarp, kcwarp-cli: no
# tests, benchmarks or fuzzers; scripts/test.sh builds those) and runs the main job: the GUI on a
# bundled example when a display is available, otherwise the headless demo (writes ./out/demo).
# A build/ configured by scripts/build.sh or test.sh keeps its tests: only the two targets are built.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --run
if [ -f build/CMakeCache.txt ]; then
  cmake -S . -B build >/dev/null
else
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DKC_BUILD_TESTS=OFF -DKC_BUILD_BENCH=OFF
fi
cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target kcwarp kcwarp-cli
if [ -n "${DISPLAY:-}" ] && [ -x build/app/kcwarp ]; then
  exec build/app/kcwarp "$@"
fi
exec build/app/kcwarp-cli demo --out out/demo "$@"
