#!/usr/bin/env bash
# The sanitized checks: builds build-asan/ (scripts/sanitized_build.sh: clang, Debug with asserts,
# AddressSanitizer and UndefinedBehaviorSanitizer), runs unit tests there — any sanitizer report
# or failed assert fails the test that triggered it — then fuzzes every loader for SECONDS
# (default 60) with the same build (scripts/fuzz.sh).
#   bash scripts/sanitize.sh [SECONDS]        every core, sampling and app test not labelled slow
#   bash scripts/sanitize.sh --short [SECONDS]   only the test files of KC_SANITIZED_SHORT_TESTS
#                                                (tests/CMakeLists.txt; one executable,
#                                                kc_sanitized_short_tests), then the fuzzers
# Neither fits in CI next to the Release build and suite (scripts/test.sh runs the fuzzers only).
# The whole set is slow: its tests summed 2,590 s in one run on a loaded machine (most
# of it the LBC, rigidity, per-sample QP, stick-figure and sampling tests), and building its
# test executables (core_tests, sampling_tests, app_tests) under the sanitizers costs about as much again.
# Leak detection is off until a run shows the third-party libraries (OpenMP, GLPK, CLP) free of
# leak reports.
set -euo pipefail
cd "$(dirname "$0")/.."
short=0
if [ "${1:-}" = "--short" ]; then short=1; shift; fi
seconds="${1:-60}"
jobs="$(nproc 2>/dev/null || echo 2)"
# One build at -O1 serves the tests and the fuzzers (scripts/fuzz.sh alone builds build-fuzz/ at -O0).
export KC_SANITIZED_DIR=build-asan KC_SANITIZED_OPT=-O1
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1"
if [ "$short" = 1 ]; then
  bash scripts/sanitized_build.sh kc_sanitized_short_tests kc_fuzz_targets
  # One GoogleTest shard per core; each prints its failures, and xargs fails when any failed.
  seq 0 $((jobs - 1)) | GTEST_TOTAL_SHARDS="$jobs" xargs -P "$jobs" -I{} sh -c \
    'if GTEST_SHARD_INDEX={} build-asan/tests/kc_sanitized_short_tests --gtest_brief=1 > build-asan/short-{}.log 2>&1; then echo "shard {}: passed (sanitized)"; else cat build-asan/short-{}.log; echo "shard {}: FAILED (sanitized)"; exit 1; fi'
else
  bash scripts/sanitized_build.sh kc_fast_tests kc_fuzz_targets
  ctest --test-dir build-asan -L "^(core|sampling|app)$" -LE slow --output-on-failure -j"$jobs" --timeout 900
fi
bash scripts/fuzz.sh "$seconds"
