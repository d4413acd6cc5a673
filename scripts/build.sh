#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root) and builds kcwarp into build/ (all cores; Ninja for a
# new build/). Arguments go to CMake's configure step (scripts/test.sh passes -DKC_BUILD_BENCH=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Ninja for a new build/: it compiles a target's files while the targets it links are still
# building, which keeps both cores of a small machine busy (make waits target by target).
generator=()
[ ! -f build/CMakeCache.txt ] && command -v ninja > /dev/null && generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DKC_BUILD_TESTS=ON -DKC_BUILD_BENCH=ON "$@"  # ON: a build/ that scripts/run.sh configured had them off
cmake --build build -j"$(nproc 2>/dev/null || echo 2)"
