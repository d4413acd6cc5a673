#!/usr/bin/env bash
# Builds the given targets of kcwarp's sanitized build in build-asan/: clang, Debug (asserts on) at
# -O1 with AddressSanitizer, UndefinedBehaviorSanitizer (any report is fatal) and libFuzzer's
# coverage, without the GUI and benchmarks. One build serves the unit tests (target kc_fast_tests)
# and the fuzz targets (kc_fuzz_targets), so the fuzzers exercise instrumented core, sampling and
# app code. Used by scripts/sanitize.sh and scripts/fuzz.sh.
#   bash scripts/sanitized_build.sh kc_fast_tests kc_fuzz_targets
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
if [ -f build-asan/CMakeCache.txt ] && ! grep -q "^KC_BUILD_FUZZ:BOOL=ON" build-asan/CMakeCache.txt; then
  rm -rf build-asan
fi
# Configured every time (it is quick when nothing changed), so targets added since are known.
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DKC_BUILD_GUI=OFF -DKC_BUILD_BENCH=OFF \
    -DKC_BUILD_FUZZ=ON "${launcher[@]}" -DCMAKE_CXX_FLAGS="$sanitize -fsanitize=fuzzer-no-link" \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DCMAKE_EXE_LINKER_FLAGS="$sanitize" > /dev/null
cmake --build build-asan -j"$(nproc 2>/dev/null || echo 2)" --target "$@"
