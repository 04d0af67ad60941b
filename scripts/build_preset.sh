#!/usr/bin/env bash
# Configures and builds one CMake preset of CMakePresets.json (release, debug, sanitize, fuzz) with Ninja.
# A build directory configured earlier by another generator (the Makefiles of older checkouts) is reconfigured
# from scratch; what else it holds (build/npm) stays.
# Usage: scripts/build_preset.sh PRESET [cmake --build options...]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=$1
shift
dir=build
[ "$preset" = release ] || dir="build-$preset"
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
  echo "pleat: $dir/ was configured by another generator; reconfiguring it with Ninja" >&2
  rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
fi
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" "$@"
