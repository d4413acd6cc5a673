#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp and runs the whole test suite, then
# fuzzes every loader for 10 s under AddressSanitizer and UndefinedBehaviorSanitizer (the
# sanitized build, scripts/sanitized_build.sh, takes the rest of CI's 30 minutes on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
bash scripts/fuzz.sh 10
