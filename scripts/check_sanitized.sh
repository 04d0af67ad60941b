#!/usr/bin/env bash
# The hardening checks CI runs after the test suite:
#  1. the whole test suite in a Debug build under AddressSanitizer + UndefinedBehaviorSanitizer (kinetic
#     invariant checks on, as in every Debug build; 40 cases per property instead of 200) in build-sanitize/;
#  2. every libFuzzer harness of tests/fuzz/ (clang, sanitizers on) for a short run on its corpus, in build-fuzz/.
# Any sanitizer report, crash, hang or failed test fails the script.
# Usage: scripts/check_sanitized.sh [seconds per fuzz harness, default 30]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
jobs=$(nproc 2>/dev/null || echo 2)

cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Debug -DPLEAT_SANITIZE=ON -DPLEAT_BUILD_BENCH=OFF \
      -DPLEAT_PROPERTY_CASES=40 >/dev/null
cmake --build build-sanitize -j "$jobs"
(cd build-sanitize &&
 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
 ctest --output-on-failure -j "$jobs" --timeout 1800)

CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLEAT_FUZZ=ON \
      -DPLEAT_BUILD_TESTS=OFF -DPLEAT_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j "$jobs"
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
