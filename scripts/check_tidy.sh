#!/usr/bin/env bash
# The house lint: clang-tidy with the project's .clang-tidy over every C++ file of the project (build/'s
# compile_commands.json, made by scripts/setup.sh), warnings as errors. About 15 minutes on 2 cores, so it is
# not part of CI's time budget; run it before a release or after large changes.
# Usage: scripts/check_tidy.sh [build directory, default build]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/compile_commands.json" ] || { echo "check_tidy: no $build/compile_commands.json (run scripts/setup.sh)" >&2; exit 2; }
run-clang-tidy -p "$build" -j "$(nproc 2>/dev/null || echo 2)" -quiet \
  "$PWD/(support|cli|sim_io|static_core|kinetic|shading|tests|bench)/.*\.cpp$"
# The function-size check over every file (the ctest function_size checks the files a branch changed).
python3 tests/tools/check_function_size.py . "$build" --all
