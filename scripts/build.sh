#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root) and builds kcwarp into build/ (all cores). Arguments
# go to CMake's configure step (scripts/test.sh passes -DKC_BUILD_BENCH=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DKC_BUILD_TESTS=ON -DKC_BUILD_BENCH=ON "$@"  # ON: a build/ that scripts/run.sh configured had them off
cmake --build build -j"$(nproc 2>/dev/null || echo 2)"
