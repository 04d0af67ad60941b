#!/usr/bin/env bash
# The cloth in its scene: accuracy against ray-traced truth of the scene and the cost of the occluders, on
# every bundled real sequence with its colliders (bench/occluders_bench.cpp), and again on the rucked sleeve
# with a 20k-triangle torso (data/rucked/rucked_body.obj). Writes bench/results/occluders.md. About a
# minute on 2 cores.
#
# Usage: bench/run_occluders.sh      (BUILD_DIR: build directory, default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" --target occluders_bench -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
bench="$build_dir/bench/occluders_bench"
{
  echo "# The cloth in its scene"
  echo
  echo "Written by \`bench/run_occluders.sh\` on commit $(git rev-parse --short HEAD): $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores (shared)."
  echo "Last frame of each bundled sequence, with the colliders it was simulated against (data/README.md)."
  echo "Error: mean and p95 of |A − A_rays| over every vertex and side, against 4096 cosine-weighted rays cast in"
  echo "the scene itself (colliders and ground included), for the cones computed with the colliders (in its scene)"
  echo "and without them (the cloth alone). Cost: median CPU ms of a frame over the last 10 frames, one thread, the"
  echo "cloth alone and in its scene alternated frame by frame; the kinetic engine keeps static occluders' chains."
  echo
  "$bench" --rays=4096
  echo
  echo "With an occluding body of 20,160 triangles (data/rucked/rucked_body.obj, a torso at the arm's end) beside the arm:"
  echo
  "$bench" --rays=4096 --sequences=rucked --body=data/rucked/rucked_body.obj
} > bench/results/occluders.md
cat bench/results/occluders.md
