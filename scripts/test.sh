#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp and runs the whole test suite:
# the Release build's tests (fast and slow), the core, sampling and app tests again in a Debug
# build with AddressSanitizer and UndefinedBehaviorSanitizer (scripts/test_asan.sh), and every
# libFuzzer target for a minute from its seed corpus (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
bash scripts/test_asan.sh
bash scripts/fuzz.sh "${KC_FUZZ_SECONDS:-60}"
