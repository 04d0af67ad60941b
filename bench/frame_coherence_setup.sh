# Sourced by the frame-coherence scripts (run_frame_coherence.sh, run_error_cost.sh), from the repository root,
# with $build_dir set: sets $python to the first Python that has matplotlib (a pyenv/venv python3 on PATH may not
# see Debian's python3-matplotlib) and builds bench/frame_coherence_bench and bench/coherence_cases_bench in Release. $1: the calling script's name,
# for the message when matplotlib is missing.
python=""
for candidate in python3 /usr/bin/python3; do
  if "$candidate" -c "import matplotlib" 2>/dev/null; then python="$candidate"; break; fi
done
[ -n "$python" ] || { echo "$1: matplotlib is missing (Debian: apt-get install python3-matplotlib)" >&2; exit 2; }

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" --target frame_coherence_bench coherence_cases_bench -j "$(nproc 2>/dev/null || echo 2)"
