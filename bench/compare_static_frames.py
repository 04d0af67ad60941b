#!/usr/bin/env python3
"""A change to the static core against a baseline build, in one run: the static engine's frame time on one
thread, per sequence, for two `pleat` executables run alternately (so both see the same machine load).

Sequences: every real one in data/ (frames 60-71) and the generated kinds at 3,025 vertices (frames 1-11)
and 29,929 vertices (frames 1-2), generated once into a scratch directory. Per sequence and executable the
median of the per-frame times (`pleat visibility --stats`, first frame of each run dropped) over all
repetitions; µs per slice vertex from the same frames. Writes a markdown table to stdout (or --out).

    bench/compare_static_frames.py BASE_PLEAT NEW_PLEAT [--reps 3] [--out FILE]

To build a baseline: `git worktree add /tmp/base <commit>` and build its `pleat` target in Release.
Debian python3 only.
"""

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GENERATED = ["curtain", "roll", "flag", "sleeve"]


def sequences(scratch, generator):
    out = []
    data = os.path.join(ROOT, "data")
    for name in sorted(os.listdir(data)):
        base = os.path.join(data, name, name)
        if os.path.exists(base + ".obj") and os.path.exists(base + ".pc2"):
            out.append((name, base, "60:72"))
    for size, resolution, frames, run in (("3k", 55, 12, "0:12"), ("30k", 173, 3, "0:3")):
        for kind in GENERATED:
            base = os.path.join(scratch, kind + size)
            if not os.path.exists(base + ".pc2"):
                subprocess.run([generator, "generate", kind, "-o", base + ".obj", "--resolution", str(resolution),
                                "--frames", str(frames)], check=True, stdout=subprocess.DEVNULL)
            out.append((kind + " " + size, base, run))
    return out


def frame_times(exe, base, frames, scratch):
    stats = os.path.join(scratch, "stats.json")
    timings = os.path.join(scratch, "timings.json")
    # Since the MPI scale-out, the seconds are in --timings (--stats holds only what the frames determine);
    # older executables have them in --stats.
    has_timings = "--timings" in subprocess.run([exe, "visibility", "--help"], capture_output=True, text=True).stdout
    subprocess.run([exe, "visibility", base + ".obj", "--cache", base + ".pc2", "--engine", "static", "--serial",
                    "--frames", frames, "-o", os.path.join(scratch, "out.csv"), "--stats", stats]
                   + (["--timings", timings] if has_timings else []),
                   check=True, stdout=subprocess.DEVNULL)
    fr = json.load(open(stats))["frames"]
    seconds = [f["seconds"] for f in json.load(open(timings if has_timings else stats))["frames"]]
    kept = slice(1, None) if len(fr) > 1 else slice(None)
    return seconds[kept], [f["slice_vertices"] for f in fr][kept]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("base")
    ap.add_argument("new")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out")
    args = ap.parse_args()
    lines = []
    with tempfile.TemporaryDirectory(prefix="pleat-compare-") as scratch:
        started = datetime.datetime.now()
        lines.append(f"Static frame, one thread, medians over {args.reps} alternating runs per executable "
                     f"({platform.node()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f} at the start, "
                     f"{started:%Y-%m-%d %H:%M}).")
        lines.append(f"base: `{args.base}`; new: `{args.new}`.")
        lines.append("")
        lines.append("| sequence | slice vertices | base ms / frame | new ms / frame | new ÷ base | base µs / slice vertex "
                     "| new µs / slice vertex |")
        lines.append("|---|---|---|---|---|---|---|")
        for name, base, frames in sequences(scratch, args.new):
            times = {"base": [], "new": []}
            counts = []
            for _ in range(args.reps):
                for which, exe in (("base", args.base), ("new", args.new)):
                    t, sv = frame_times(exe, base, frames, scratch)
                    times[which] += t
                    counts += sv
            sv = statistics.median(counts)
            b, n = statistics.median(times["base"]), statistics.median(times["new"])
            lines.append(f"| {name} | {sv:,.0f} | {b * 1e3:.1f} | {n * 1e3:.1f} | {n / b:.2f} | {b * 1e6 / sv:.2f} | "
                         f"{n * 1e6 / sv:.2f} |")
            print(lines[-1], file=sys.stderr, flush=True)
        lines.append("")
        lines.append(f"Run time {(datetime.datetime.now() - started).total_seconds():.0f} s.")
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
