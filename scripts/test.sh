#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp (without the Google Benchmark
# targets) and runs the whole test suite, then fuzzes every loader for 10 s under AddressSanitizer
# and UndefinedBehaviorSanitizer (scripts/fuzz.sh; the sanitized build, scripts/sanitized_build.sh,
# takes the rest of CI's 30 minutes on 2 cores). The sanitized unit tests (scripts/sanitize.sh)
# do not fit in that time.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DKC_BUILD_BENCH=OFF  # the benchmarks are not tests; CI time is short
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
bash scripts/fuzz.sh 10
