#!/usr/bin/env bash
# Builds the given targets of a sanitized build of kcwarp: clang, Debug (asserts on) with
# AddressSanitizer, UndefinedBehaviorSanitizer (any report is fatal) and libFuzzer's coverage,
# without the GUI and benchmarks. One build serves the unit tests (targets kc_fast_tests: core_tests,
# sampling_tests, app_tests; kc_sanitized_short_tests) and the fuzz targets (kc_fuzz_targets), so
# the fuzzers exercise instrumented core, sampling and app code. Used by scripts/sanitize.sh and
# scripts/fuzz.sh.
#   KC_SANITIZED_DIR   the build folder (default build-asan)
#   KC_SANITIZED_OPT   the optimization flag (default -O1; scripts/fuzz.sh alone builds build-fuzz at
#                      -O0, which compiles in about half the time: the fuzzers run only seconds)
#   bash scripts/sanitized_build.sh kc_fast_tests kc_fuzz_targets
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
# lld when present (scripts/setup.sh installs it): a sanitized fuzzer links in ~2 s, ~11 s with GNU ld.
linker="$sanitize"
command -v ld.lld > /dev/null && linker="$linker -fuse-ld=lld"
dir="${KC_SANITIZED_DIR:-build-asan}"
opt="${KC_SANITIZED_OPT:--O1}"
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q "^KC_BUILD_FUZZ:BOOL=ON" "$dir/CMakeCache.txt"; then
  rm -rf "$dir"
fi
generator=()  # Ninja for a new build folder, as scripts/build.sh
[ ! -f "$dir/CMakeCache.txt" ] && command -v ninja > /dev/null && generator=(-G Ninja)
# Configured every time (it is quick when nothing changed), so targets added since are known.
CC=clang CXX=clang++ cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Debug -DKC_BUILD_GUI=OFF -DKC_BUILD_BENCH=OFF \
    -DKC_BUILD_FUZZ=ON -DKC_TEST_OPTIMIZATION= "${launcher[@]}" -DCMAKE_CXX_FLAGS="$sanitize -fsanitize=fuzzer-no-link" \
    -DCMAKE_CXX_FLAGS_DEBUG="$opt -gline-tables-only" -DCMAKE_EXE_LINKER_FLAGS="$linker" > /dev/null
cmake --build "$dir" -j"$(nproc 2>/dev/null || echo 2)" --target "$@"
