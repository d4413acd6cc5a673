#!/usr/bin/env bash
# Debug build (asserts on) with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/,
# at -O1 and without the GUI and benchmarks, running the core, sampling and app tests that are not
# labelled slow. Any sanitizer report fails the test that triggered it. Leak detection is off
# until a run shows the third-party libraries (OpenMP, GLPK, CLP) free of leak reports.
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DKC_BUILD_GUI=OFF -DKC_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1 $sanitize" -DCMAKE_EXE_LINKER_FLAGS="$sanitize"
cmake --build build-asan -j"$(nproc 2>/dev/null || echo 2)" --target kc_fast_tests
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1"
ctest --test-dir build-asan -L "^(core|sampling|app)$" -LE slow --output-on-failure \
  -j"$(nproc 2>/dev/null || echo 2)" --timeout 600
