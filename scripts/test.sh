#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp and runs the whole test suite, then,
# under AddressSanitizer and UndefinedBehaviorSanitizer (a Debug build with asserts,
# scripts/sanitized_build.sh), runs CI's share of the unit tests and fuzzes every loader for 10 s
# (scripts/sanitize.sh --ci; together they take the rest of CI's 30 minutes on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
bash scripts/sanitize.sh --ci 10
