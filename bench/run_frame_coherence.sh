#!/usr/bin/env bash
# The frame-coherence benchmark (issues 6 and 11), in one command: builds bench/frame_coherence_bench in Release,
# runs it with its defaults (every real sequence in data/ and the generated kinds at 3,025 and 29,929 vertices;
# u = 0.5, 1, 2, 4, 8; static, kinetic, the paper's plan and Embree over an 11-step ray ladder at 1 and 2 threads;
# see the flags at the top of bench/frame_coherence_bench.cpp) and draws the plots. Everything goes to
# bench/results/: frame_coherence.md, frame_coherence.csv, frame_coherence_headline.md, frame_coherence_*.png; a full
# run also puts the headline tables into docs/benchmarks.md, between its markers. About 25-30 minutes on 2 shared
# cores. The README is never edited.
#
# It also runs the coherence cases (bench/coherence_cases_bench.cpp: a still cloth, a lifted corner, moving
# patches of 1%, 10% and 50% of the vertices, the real sequences at 1x, 4x and 8x; kinetic ÷ static per frame) and
# plots them against the share of vertices that moved: frame_coherence_cases.{csv,md,png}; a full run puts that
# table into docs/benchmarks.md too. The cases alone (about 3 minutes): bench/run_frame_coherence.sh --cases
# [flags for coherence_cases_bench]; with no further flags it updates docs/benchmarks.md.
#
# Usage: bench/run_frame_coherence.sh [flags for frame_coherence_bench, e.g. --sequences drape --frames 12]
#        bench/run_frame_coherence.sh --cases [flags for coherence_cases_bench, e.g. --frames 8]
#   BUILD_DIR   build directory (default: build)
# Exit status: the benchmark's (1 when a method failed or static and kinetic disagreed; the outputs say where).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
out=bench/results

source bench/frame_coherence_setup.sh run_frame_coherence  # sets $python, builds the benchmark

# Puts $1 (a markdown file) into docs/benchmarks.md between the markers "<!-- $2: begin -->" and "... end -->".
into_benchmarks() {
  "$python" - "$1" docs/benchmarks.md "$2" <<'PY'
import sys
table, target, name = sys.argv[1], sys.argv[2], sys.argv[3]
begin, end = "<!-- " + name + ": begin -->", "<!-- " + name + ": end -->"
text = open(target).read()
if begin in text and end in text:
    text = text[: text.index(begin) + len(begin)] + "\n" + open(table).read() + text[text.index(end):]
    open(target, "w").write(text)
else:
    print("run_frame_coherence: no " + name + " markers in " + target + "; tables left in bench/results", file=sys.stderr)
PY
}

# The coherence cases: the program, its plot, and (without flags) its table into docs/benchmarks.md.
run_cases() {
  "$build_dir/bench/coherence_cases_bench" --out "$out" "$@" || status=$?
  "$python" bench/plot_coherence_cases.py "$out/frame_coherence_cases.csv" --out "$out"
  if [ "$#" -eq 0 ] && [ -f "$out/frame_coherence_cases.md" ]; then
    into_benchmarks "$out/frame_coherence_cases.md" "coherence cases"
  fi
}

start=$(date +%s)
status=0
if [ "${1:-}" = "--cases" ]; then
  shift
  run_cases "$@"
  echo "run_frame_coherence: $(( $(date +%s) - start )) s; wrote $out/frame_coherence_cases.{csv,md,png}" >&2
  exit "$status"
fi
"$build_dir/bench/frame_coherence_bench" --out "$out" "$@" || status=$?
"$python" bench/plot_frame_coherence.py "$out/frame_coherence.csv" --out "$out"
# A full run (no flags) also puts its headline tables into docs/benchmarks.md, between the markers there, and
# runs the coherence cases.
if [ "$#" -eq 0 ] && [ -f "$out/frame_coherence_headline.md" ]; then
  into_benchmarks "$out/frame_coherence_headline.md" "frame-coherence headline"
  run_cases
  BUILD_DIR="$build_dir" bash bench/make_front_picture.sh  # the README's picture, from today's engine
fi
echo "run_frame_coherence: $(( $(date +%s) - start )) s; wrote $out/frame_coherence.md, $out/frame_coherence.csv," \
     "$out/frame_coherence_headline.md, $out/frame_coherence_*.png" >&2
exit "$status"
