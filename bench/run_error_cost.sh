#!/usr/bin/env bash
# Error against cost (issue 42): the static engine under a grid of plans (orientations x spacing x storage rule)
# beside Embree's ray ladder, on the real sequences in data/, each in its scene, u = 1, one thread, in one command.
# Builds bench/frame_coherence_bench in Release, runs it with --plans (the grid below; the default plan and the
# paper's are in it, checked against the static and paper rows), and draws the plot. Writes
# bench/results/frame_coherence_error_cost.{csv,md,png}; the markdown's "Plans" tables hold each plan's error,
# CPU time, Pareto front and ratio to Embree at matched error. About 15-25 minutes on 2 shared cores.
#
# Usage: bench/run_error_cost.sh [more flags for frame_coherence_bench, e.g. --sequences drape --frames 12]
#   BUILD_DIR   build directory (default: build)
#   PLANS       the grid (default below)
#   SEQUENCES   default drape,layered,pile,rucked (the real sequences in data/)
# Exit status: the benchmark's (1 when a method failed or a repeated plan disagreed; the outputs say where).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
out=bench/results
name=frame_coherence_error_cost
# The paper's 6 axis orientations (nearer-endpoint: the paper's plan at 1 edge; aimed-on-fan: pleat's storage on
# them), then 8 (the default), 12, 16 and 24 spread orientations, 1/2 and 1 average edge apart, with the default
# storage (aimed-on-fan) and the one before it (interpolated-on-fan); aimed-on-fan also 3/4 edge apart (12 at 3/4
# cuts about as many planes as 8 at 1/2, 16 at 1 as many: more orientations at equal cost).
grid=""
for s in 0.5 1; do for r in nearer-endpoint aimed-on-fan; do grid+="6:$s:$r,"; done; done
for o in 8 12 16 24; do
  for s in 0.5 1; do for r in aimed-on-fan interpolated-on-fan; do grid+="$o:$s:$r,"; done; done
  grid+="$o:0.75:aimed-on-fan,"
done
plans="${PLANS:-${grid%,}}"

source bench/frame_coherence_setup.sh run_error_cost  # sets $python, builds the benchmark

tmp="$build_dir/error_cost"  # the benchmark's own file names; copied to $out under this run's names
mkdir -p "$tmp"
start=$(date +%s)
status=0
"$build_dir/bench/frame_coherence_bench" --out "$tmp" --sequences "${SEQUENCES:-drape,layered,pile,rucked}" \
  --upsample 1 --threads 1 --plans "$plans" "$@" || status=$?
[ -f "$tmp/frame_coherence.csv" ] || exit "$status"
cp "$tmp/frame_coherence.csv" "$out/$name.csv"
cp "$tmp/frame_coherence.md" "$out/$name.md"
"$python" bench/plot_frame_coherence.py "$out/$name.csv" --out "$out" --plots error-cost
echo "run_error_cost: $(( $(date +%s) - start )) s; wrote $out/$name.csv, $out/$name.md, $out/$name.png" >&2
exit "$status"
