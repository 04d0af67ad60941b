#!/usr/bin/env bash
# The hardening checks CI runs after the test suite:
#  1. the whole test suite in a Debug build (at -O1) under AddressSanitizer + UndefinedBehaviorSanitizer (kinetic
#     invariant checks on, as in every Debug build; 40 cases per property instead of 200): preset sanitize,
#     build-sanitize/;
#  2. every libFuzzer harness of tests/fuzz/ (clang, sanitizers on) for a short run on its corpus, one per core at
#     a time: preset fuzz, build-fuzz/.
# Any sanitizer report, crash, hang or failed test fails the script.
# Usage: scripts/check_sanitized.sh [seconds per fuzz harness, default 30]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
jobs=$(nproc 2>/dev/null || echo 2)

scripts/build_preset.sh sanitize
ctest --preset sanitize -j "$jobs"  # ASAN_OPTIONS, UBSAN_OPTIONS: the preset's

scripts/build_preset.sh fuzz
# One harness per core at a time (each is one libFuzzer process); every log is kept in build-fuzz/NAME.log.
fuzz_one() {
  local harness=$1 name
  name=$(basename "$harness")
  mkdir -p "build-fuzz/corpus/$name"  # new inputs go here; the committed seeds stay as they are
  if ! "$harness" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
       "build-fuzz/corpus/$name" "tests/fuzz/corpus/$name" >"build-fuzz/$name.log" 2>&1; then
    tail -n 60 "build-fuzz/$name.log"
    echo "fuzz: $name found a problem (input saved by libFuzzer as crash-*/timeout-*/oom-*)" >&2
    return 1
  fi
  echo "fuzz: $name $(grep -E "stat::number_of_executed_units" "build-fuzz/$name.log")"
}
failed=0
running=0
for harness in build-fuzz/tests/fuzz/fuzz_*; do
  echo "fuzz: $(basename "$harness") for ${seconds} s"
  fuzz_one "$harness" &
  running=$((running + 1))
  if ((running >= jobs)); then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while ((running > 0)); do
  wait -n || failed=1
  running=$((running - 1))
done
exit "$failed"
