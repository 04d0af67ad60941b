#!/usr/bin/env bash
# The README's picture: the bundled drape, frame 60, in the scene it was simulated in (its turning table and the
# ground y = 0) under a cloudy sky, shaded from pleat's cones beside a 1024-path reference and their difference
# (pleat compare). Writes bench/results/compare_drape.png and prints compare's summary line. About 15 s.
# bench/run_frame_coherence.sh runs it after a full run.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
d=data/drape
"$build_dir/cli/pleat" compare "$d/drape.obj" --cache "$d/drape.pc2" --frame 60 --light cloudy:1 \
  --occluder "$d/drape_colliders.obj,cache=$d/drape_colliders.pc2" --ground y=0 --paths 1024 \
  --camera 1.5,1.25,1.9,0.05,0.45,0,0,1,0,40 -o bench/results/compare_drape.png
