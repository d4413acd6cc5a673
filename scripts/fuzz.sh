#!/usr/bin/env bash
# Runs kcwarp's libFuzzer targets (tests/fuzz: cage, pose, session, structure, points CSV, image
# header) from a sanitized build (scripts/sanitized_build.sh: clang, AddressSanitizer,
# UndefinedBehaviorSanitizer; build-fuzz/ at -O0 unless KC_SANITIZED_DIR and KC_SANITIZED_OPT name
# another, as scripts/sanitize.sh does), each for SECONDS (default 40) from the
# committed seed corpus (tests/fuzz/corpus/; new inputs go to a scratch folder), one target per
# core at a time (FUZZ_JOBS=1: one target after the other). A finding — a crash, a sanitizer
# report, an input taking more than 20 s, or a peak above 1 GB of memory (-rss_limit_mb=1024) —
# fails the run with the target's log and its reproducer in BUILD/finding-TARGET-*.
#   bash scripts/fuzz.sh          # 40 s per target
#   bash scripts/fuzz.sh 600      # a long run: 10 minutes per target
#   bash scripts/fuzz.sh 600 session   # one target
# Reproduce a finding: build-fuzz/tests/fuzz/fuzz_TARGET build-fuzz/finding-TARGET-crash-...
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-40}"
all_targets="cage pose session structure points_csv image_header"
targets="${2:-$all_targets}"
jobs="${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}"
export KC_SANITIZED_DIR="${KC_SANITIZED_DIR:-build-fuzz}" KC_SANITIZED_OPT="${KC_SANITIZED_OPT:--O0}"
bash scripts/sanitized_build.sh kc_fuzz_targets
build="$KC_SANITIZED_DIR"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# One target: its summary line on success, its log on a finding (exit 1).
run_one() {
  local t="$1" log="$work/$1.log"
  mkdir -p "$work/$t"
  # OMP_NUM_THREADS=1: the session target factorizes small kernels; threads only add noise.
  if OMP_NUM_THREADS=1 "$build"/tests/fuzz/fuzz_"$t" "$work/$t" "tests/fuzz/corpus/$t" -max_total_time="$seconds" -timeout=20 \
      -rss_limit_mb=1024 -print_final_stats=1 -artifact_prefix="$build/finding-$t-" > "$log" 2>&1; then
    local runs rss cov
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    rss=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
    echo "fuzz_$t: ${seconds} s, $runs inputs, coverage $cov edges, peak RSS ${rss} MB: no finding"
  else
    echo "fuzz_$t: FINDING (log below; reproducer in $build/finding-$t-*)"
    tail -60 "$log"
    return 1
  fi
}
export -f run_one
export seconds work build
# xargs runs `jobs` targets side by side and exits non-zero when any of them had a finding.
printf '%s\n' $targets | xargs -P "$jobs" -I{} bash -c 'run_one "$@"' _ {}
