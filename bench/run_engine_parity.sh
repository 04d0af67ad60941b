#!/usr/bin/env bash
# The default engine never loses (issue 38): the kinetic engine (the default) against the static one, per
# frame, on every bundled real sequence at the native frame rate and at half of it (every other frame of the
# cache, where carrying a slice pays least). Each sequence's runs alternate the engines REPEAT times (default
# 3) so that load from other jobs spreads over both; a cell is the median wall time per frame of
# `pleat visibility --serial --frames FRAMES` over every timed frame of every run (a run's first frame, which
# builds the engine, not counted). The CSVs of the two engines are compared byte for byte.
# Writes bench/results/engine_parity.md. About 6 minutes on 2 cores.
#
# Usage: bench/run_engine_parity.sh      (BUILD_DIR: build directory, default build; REPEAT; FRAMES)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
repeat="${REPEAT:-3}"
frames="${FRAMES:-10:40}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" --target pleat -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
pleat="$PWD/$build_dir/cli/pleat"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Half rate: a PC2 holding every other frame of the cache (same header, half the samples, twice the rate).
halve() {
  python3 - "$1" "$2" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
magic, version, points, start, rate, samples = struct.unpack_from("<12siiffi", data, 0)
size = points * 12
frames = [data[32 + i * size:32 + (i + 1) * size] for i in range(0, samples, 2)]
header = struct.pack("<12siiffi", magic, version, points, start, rate * 2, len(frames))
open(sys.argv[2], "wb").write(header + b"".join(frames))
PY
}

rows=()
for name in drape layered pile rucked; do
  obj="data/$name/$name.obj"
  halve "data/$name/$name.pc2" "$work/${name}_half.pc2"
  for rate in native half; do
    pc2="data/$name/$name.pc2"
    [ "$rate" = half ] && pc2="$work/${name}_half.pc2"
    for r in $(seq "$repeat"); do
      for engine in static kinetic; do
        "$pleat" visibility "$obj" --cache "$pc2" -o "$work/$name.$rate.$engine.csv" --serial --frames "$frames" \
          --engine "$engine" --timings "$work/$name.$rate.$engine.$r.json" >/dev/null
      done
      echo "[engine_parity] $name $rate run $r" >&2
    done
    same=yes
    cmp -s "$work/$name.$rate.static.csv" "$work/$name.$rate.kinetic.csv" || same=NO
    rows+=("$name $rate $same")
  done
done

python3 - "$work" "$repeat" "$frames" "$(git rev-parse --short HEAD)" "$(nproc)" \
  "$(cut -d' ' -f1-3 /proc/loadavg)" "${rows[@]}" > bench/results/engine_parity.md <<'PY'
import glob, json, statistics, sys
work, repeat, frames, commit, cores, load = sys.argv[1:7]
rows = [r.split() for r in sys.argv[7:]]
cpu = open("/proc/cpuinfo").read().split("model name")[1].split("\n")[0].strip(" :\t")
def frame_ms(name, rate, engine):
    times = []
    for path in sorted(glob.glob(f"{work}/{name}.{rate}.{engine}.*.json")):
        times += [f["seconds"] * 1e3 for f in json.load(open(path))["frames"] if not f.get("chunk_start")]
    return statistics.median(times)
print("# The default engine against the static one\n")
print(f"Written by `bench/run_engine_parity.sh` on commit {commit}: {cpu}, {cores} cores (shared; load average "
      f"at the end {load}). Median wall ms per frame of `pleat visibility --serial --frames {frames}` over "
      f"{repeat} alternated runs of each engine (a run's first frame not counted). Half rate: every other frame "
      "of the cache. CSV: the two engines' outputs compared byte for byte.\n")
print("| sequence | rate | static ms | kinetic ms | kinetic ÷ static | CSV identical |")
print("|---|---|---:|---:|---:|---|")
for name, rate, same in rows:
    s, k = frame_ms(name, rate, "static"), frame_ms(name, rate, "kinetic")
    print(f"| {name} | {rate} | {s:.1f} | {k:.1f} | {k / s:.3f} | {same} |")
PY
cat bench/results/engine_parity.md
