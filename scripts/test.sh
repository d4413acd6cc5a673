#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp and runs the whole test suite, then
# fuzzes every loader for a minute under AddressSanitizer and UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
bash scripts/fuzz.sh 60
