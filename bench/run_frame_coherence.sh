#!/usr/bin/env bash
# The frame-coherence benchmark (issues 6 and 11), in one command: builds bench/frame_coherence_bench in Release,
# runs it with its defaults (every real sequence in data/ and the generated kinds at 3,025 and 29,929 vertices;
# u = 0.5, 1, 2, 4, 8; static, kinetic, the paper's plan and Embree over an 11-step ray ladder at 1 and 2 threads;
# see the flags at the top of bench/frame_coherence_bench.cpp) and draws the plots. Everything goes to
# bench/results/: frame_coherence.md, frame_coherence.csv, frame_coherence_headline.md, frame_coherence_*.png; a full
# run also puts the headline tables into docs/benchmarks.md, between its markers. About 25-30 minutes on 2 shared
# cores. The README is never edited.
#
# Usage: bench/run_frame_coherence.sh [flags for frame_coherence_bench, e.g. --sequences drape --frames 12]
#   BUILD_DIR   build directory (default: build)
# Exit status: the benchmark's (1 when a method failed or static and kinetic disagreed; the outputs say where).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
out=bench/results

source bench/frame_coherence_setup.sh run_frame_coherence  # sets $python, builds the benchmark

start=$(date +%s)
status=0
"$build_dir/bench/frame_coherence_bench" --out "$out" "$@" || status=$?
"$python" bench/plot_frame_coherence.py "$out/frame_coherence.csv" --out "$out"
# A full run (no flags) also puts its headline tables into docs/benchmarks.md, between the markers there.
if [ "$#" -eq 0 ] && [ -f "$out/frame_coherence_headline.md" ]; then
  "$python" - "$out/frame_coherence_headline.md" docs/benchmarks.md <<'PY'
import sys
headline, target = sys.argv[1], sys.argv[2]
begin, end = "<!-- frame-coherence headline: begin -->", "<!-- frame-coherence headline: end -->"
text = open(target).read()
if begin in text and end in text:
    text = text[: text.index(begin) + len(begin)] + "\n" + open(headline).read() + text[text.index(end):]
    open(target, "w").write(text)
else:
    print("run_frame_coherence: no headline markers in " + target + "; tables left in bench/results", file=sys.stderr)
PY
  BUILD_DIR="$build_dir" bash bench/make_front_picture.sh  # the README's picture, from today's engine
fi
echo "run_frame_coherence: $(( $(date +%s) - start )) s; wrote $out/frame_coherence.md, $out/frame_coherence.csv," \
     "$out/frame_coherence_headline.md, $out/frame_coherence_*.png" >&2
exit "$status"
