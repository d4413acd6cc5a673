#!/usr/bin/env bash
# The sanitized checks (CI runs them after the Release suite): builds build-asan/
# (scripts/sanitized_build.sh: clang, Debug with asserts, AddressSanitizer and
# UndefinedBehaviorSanitizer), runs the core, sampling and app tests that are not labelled slow
# there — any sanitizer report or failed assert fails the test that triggered it — then fuzzes
# every loader for SECONDS (default 60) with the same build (scripts/fuzz.sh).
# Leak detection is off until a run shows the third-party libraries (OpenMP, GLPK, CLP) free of
# leak reports.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
jobs="$(nproc 2>/dev/null || echo 2)"
bash scripts/sanitized_build.sh kc_fast_tests kc_fuzz_targets
ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1" \
  ctest --test-dir build-asan -L "^(core|sampling|app)$" -LE slow --output-on-failure -j"$jobs" --timeout 600
bash scripts/fuzz.sh "$seconds"
