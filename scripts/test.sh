#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp (without the Google Benchmark
# targets) and runs the whole test suite, then fuzzes every loader for 10 s under AddressSanitizer
# and UndefinedBehaviorSanitizer (scripts/fuzz.sh). The fuzzers' sanitized build
# (scripts/sanitized_build.sh into build-fuzz/, -O0) compiles at the lowest priority while the
# tests run: the GUI tests spend most of their time waiting for frames, and the build takes the
# cores they leave idle. The sanitized unit tests (scripts/sanitize.sh) do not fit in CI's 30
# minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DKC_BUILD_BENCH=OFF  # the benchmarks are not tests; CI time is short
export KC_SANITIZED_DIR=build-fuzz KC_SANITIZED_OPT=-O0  # scripts/fuzz.sh's defaults, spelled out
setsid nice -n 19 bash scripts/sanitized_build.sh kc_fuzz_targets > build/fuzz-build.log 2>&1 &
fuzz_build=$!  # its own process group (setsid), stopped whole when a test fails
status=0
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" --timeout 600 || status=$?
if [ "$status" -ne 0 ]; then
  kill -- -"$fuzz_build" 2> /dev/null || true
  exit "$status"
fi
if ! wait "$fuzz_build"; then
  tail -40 build/fuzz-build.log
  echo "the fuzzers' sanitized build failed (build/fuzz-build.log)"
  exit 1
fi
bash scripts/fuzz.sh 10
