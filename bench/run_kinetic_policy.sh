#!/usr/bin/env bash
# The kinetic repair policy, measured (issue 5: "the threshold measured, not guessed"): median frame time of
# `pleat visibility --serial` on the bundled drape (native rate) and a generated curtain (3,025 vertices) at
# 48 and 192 frames per motion cycle (native and 4x), for the static engine and the kinetic engine with
# --max-edit-fraction X, X in {0, 0.1, 0.25, 0.5 (the default), 1}. The runs of one
# sequence alternate engines and are repeated (REPEAT, default 2) so that load from other jobs on a shared
# machine spreads over all of them; each cell is the median over every timed frame of every repeat.
# Writes bench/results/kinetic_policy.md. About 6 minutes on 2 cores.
#
# Usage: bench/run_kinetic_policy.sh      (BUILD_DIR: build directory, default build; REPEAT)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
repeat="${REPEAT:-2}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" --target pleat -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
pleat="$PWD/$build_dir/cli/pleat"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$pleat" generate curtain -o "$work/curtain48.obj" --resolution 55 --frames 48 >/dev/null 2>&1
"$pleat" generate curtain -o "$work/curtain192.obj" --resolution 55 --frames 192 >/dev/null 2>&1
settings=(static 0 0.1 0.25 0.5 1)
run() {  # name obj pc2 frames
  local name=$1 obj=$2 pc2=$3 frames=$4
  for r in $(seq "$repeat"); do
    for x in "${settings[@]}"; do
      if [ "$x" = static ]; then
        "$pleat" visibility "$obj" --cache "$pc2" -o "$work/out.csv" --serial --frames "$frames" --engine static \
          --timings "$work/$name.$x.$r.json" 2>/dev/null
      else
        "$pleat" visibility "$obj" --cache "$pc2" -o "$work/out.csv" --serial --frames "$frames" \
          --max-edit-fraction "$x" --timings "$work/$name.$x.$r.json" 2>/dev/null
      fi
      echo "[kinetic_policy] $name X=$x run $r" >&2
    done
  done
}
run drape data/drape/drape.obj data/drape/drape.pc2 20:45
run curtain48 "$work/curtain48.obj" "$work/curtain48.pc2" 8:33
run curtain192 "$work/curtain192.obj" "$work/curtain192.pc2" 32:57

python3 - "$work" "$repeat" "$(git rev-parse --short HEAD)" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" \
  > bench/results/kinetic_policy.md <<'PY'
import json, statistics, sys, glob
work, repeat, commit, cores, load = sys.argv[1:6]
settings = ["static", "0", "0.1", "0.25", "0.5", "1"]
default = "0.5"
names = {"drape": "drape (Blender, 3,111 vertices), native rate",
         "curtain48": "curtain (3,025 vertices), 48 frames per cycle",
         "curtain192": "curtain (3,025 vertices), 192 frames per cycle (4x)"}
print("# Kinetic repair policy\n")
print(f"Written by `bench/run_kinetic_policy.sh` on commit {commit}, {cores} cores (shared; load average at the "
      f"end {load}). Median wall ms per frame of `pleat visibility --serial` over 25 frames x {repeat} runs "
      "(the first frame of a run, which builds the engine, not counted); in brackets kinetic ÷ static. "
      "X = `--max-edit-fraction X`: a slice of n slice vertices is rebuilt when more than 2 + X n of them are "
      "removed, inserted or taken out and put back in a frame.\n")
print("| sequence | static | " + " | ".join(f"kinetic X = {x}" + (" (default)" if x == default else "") for x in settings[1:])
      + f" | slices kept / rebuilt per frame, X = {default} |")
print("|---" * (len(settings) + 2) + "|")
for name, label in names.items():
    ms, stats = {}, {}
    for x in settings:
        frames = []
        for path in sorted(glob.glob(f"{work}/{name}.{x}.*.json")):
            frames += json.load(open(path))["frames"][1:]
        ms[x] = 1000 * statistics.median(f["seconds"] for f in frames)
        stats[x] = frames
    cells = [f"{ms['static']:.1f}"] + [f"{ms[x]:.1f} ({ms[x] / ms['static']:.2f})" for x in settings[1:]]
    k = [f["kinetic"] for f in stats[default]]
    repaired = statistics.mean(f["slices_repaired"] + f["slices_unchanged"] for f in k)
    rebuilt = statistics.mean(f["slices_rebuilt"] for f in k)
    print(f"| {label} | " + " | ".join(cells) + f" | {repaired:.0f} / {rebuilt:.0f} |")
PY
echo "run_kinetic_policy: wrote bench/results/kinetic_policy.md" >&2
