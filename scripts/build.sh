#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root) and builds kcwarp into build/ (all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc 2>/dev/null || echo 2)"
