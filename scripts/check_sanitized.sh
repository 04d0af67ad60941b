#!/usr/bin/env bash
# The hardening checks CI runs after the test suite:
#  1. the whole test suite in a Debug build (at -O1) under AddressSanitizer + UndefinedBehaviorSanitizer (kinetic
#     invariant checks on, as in every Debug build; 40 cases per property instead of 200): preset sanitize,
#     build-sanitize/;
#  2. every libFuzzer harness of tests/fuzz/ (clang, sanitizers on) for a short run on its corpus: preset fuzz,
#     build-fuzz/.
# Any sanitizer report, crash, hang or failed test fails the script.
# Usage: scripts/check_sanitized.sh [seconds per fuzz harness, default 30]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
jobs=$(nproc 2>/dev/null || echo 2)

scripts/build_preset.sh sanitize
ctest --preset sanitize -j "$jobs"  # ASAN_OPTIONS, UBSAN_OPTIONS: the preset's

scripts/build_preset.sh fuzz
for harness in build-fuzz/tests/fuzz/fuzz_*; do
  name=$(basename "$harness")
  mkdir -p "build-fuzz/corpus/$name"  # new inputs go here; the committed seeds stay as they are
  echo "fuzz: $name for ${seconds} s"
  log="build-fuzz/$name.log"
  if ! "$harness" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
       "build-fuzz/corpus/$name" "tests/fuzz/corpus/$name" >"$log" 2>&1; then
    tail -n 60 "$log"
    echo "fuzz: $name found a problem (input saved by libFuzzer as crash-*/timeout-*/oom-*)" >&2
    exit 1
  fi
  grep -E "stat::number_of_executed_units" "$log"
done
