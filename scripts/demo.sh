#!/usr/bin/env bash
# The main job: set up (missing Debian packages, Release build), then compute visibility cones for the bundled
# Blender cloth simulation (data/drape), on the table and ground it was simulated against, frame by frame,
# and shade it under a cloudy sky. Writes into out/:
#   out/drape.csv           per-vertex sky visibility A of both sides, every frame (frame,vertex,front,back)
#   out/drape.cones         the cones of every frame (a cone cache: the shading below reads it)
#   out/drape_stats.json    per-frame statistics of the cone computation
#   out/drape.glb           the shaded animation (flipbook glb: plays in three.js, imports into Blender)
#   out/renders/*.png       images of every 10th frame (Embree ray-cast, both cloth sides shaded, the table
#                           and the ground drawn)
#   out/renders_sky/*.png   the same frames showing A itself (viridis colour map, with a legend)
#   out/view/index.html     a page that plays the animation and relights it live from its cones (pleat view)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out
pleat=build/cli/pleat
input=(data/drape/drape.obj --cache data/drape/drape.pc2)
# The scene it was simulated in: the turning table (animated) and the ground block the cloth's sky.
scene=(--occluder data/drape/drape_colliders.obj,cache=data/drape/drape_colliders.pc2 --ground y=0)
"$pleat" info "${input[@]}"
"$pleat" visibility "${input[@]}" "${scene[@]}" -o out/drape.csv --cones out/drape.cones --stats out/drape_stats.json
"$pleat" shade "${input[@]}" "${scene[@]}" --cones out/drape.cones -o out/drape.glb --light cloudy:1.0,up=0,1,0 \
  --render out/renders --render-every 10
"$pleat" shade "${input[@]}" "${scene[@]}" --cones out/drape.cones -o - --render-mode sky-visibility \
  --render out/renders_sky --render-every 10 -q >/dev/null
"$pleat" view out/drape.glb -o out/view
echo "pleat demo: wrote $(pwd)/out/drape.glb, $(pwd)/out/renders/ and out/renders_sky/ ($(ls out/renders | wc -l) + $(ls out/renders_sky | wc -l) PNG images), $(pwd)/out/drape.csv; open $(pwd)/out/view/index.html in a browser"
