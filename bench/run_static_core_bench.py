#!/usr/bin/env python3
"""Speed of pleat's static core: builds bench/static_core_bench in Release, runs it once, and writes
bench/results/static_core.{md,csv,json} (docs/benchmarks.md; issue 3, "Speed").

Every figure in the markdown comes from that one run of one process: compute_visibility per frame at 3k,
30k and 300k vertices (curtain and roll, frame 12 of 48), one thread and two; µs per slice vertex against
the paper's 410 µs (300 MHz Pentium) and the static-core issue's targets (1.5 µs, 2 µs at 300k); the last,
most folded frame of each real Blender sequence of data/ against the drape's; the stages of the 30k curtain
frame; operator-new calls per slice vertex; and Embree ray casting (256 rays per vertex and side, BVH build included) on the
same frames and threads. Medians of repetitions; the machine may be shared, so its load is recorded too.

    bench/run_static_core_bench.py            # full run (about 8 minutes on 2 cores)
    bench/run_static_core_bench.py --quick    # 3k only, one repetition: proves the pipeline end to end

Debian python3 only (no third-party modules).
"""

import argparse
import csv
import datetime
import json
import os
import platform
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAPER_US_PER_SLICE_VERTEX = 410.0  # Stewart 1999: 20.7 s for the shirt's cones on a 300 MHz Pentium
# The static-core issue: at most 1.5 µs of CPU per slice vertex on one core, 2 µs at 300k vertices; no real
# sequence above 2x the drape's cost per slice vertex.
TARGET_US_PER_SLICE_VERTEX = 1.5
TARGET_US_PER_SLICE_VERTEX_LARGE = 2.0
LARGE_VERTICES = 100000
REAL_BOUND = 2.0


def us_per_slice_vertex(row):
    """µs of CPU per slice vertex of a benchmark row, or None when it counted no slice vertex."""
    return 1e3 * row["cpu_ms"] / row["slice_vertices"] if row.get("slice_vertices") else None


def target_for(vertices):
    return TARGET_US_PER_SLICE_VERTEX_LARGE if vertices >= LARGE_VERTICES else TARGET_US_PER_SLICE_VERTEX
STAGES = ["setup", "slicing", "triangulation", "cones_2d", "assembly_3d"]
STAGE_TEXT = {
    "setup": "setup (normals, mesh edges, candidate faces per plane)",
    "slicing": "slicing (slice_mesh)",
    "triangulation": "triangulation (SliceTriangulation::build: CDT, corners, regions)",
    "cones_2d": "2D cones (compute_slice_cones: funnel trees, range walks)",
    "assembly_3d": "3D assembly (assemble_cone + measure_cone, both sides)",
}


def run(command, **kwargs):
    print("+ " + " ".join(command), file=sys.stderr, flush=True)
    return subprocess.run(command, check=True, **kwargs)


def output_of(command):
    try:
        return subprocess.run(command, check=True, capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def machine():
    model = ""
    for line in output_of(["lscpu"]).splitlines():
        if line.startswith("Model name"):
            model = line.split(":", 1)[1].strip()
    return {
        "nproc": output_of(["nproc"]),
        "model": model,
        "kernel": platform.release(),
        "compiler": output_of(["c++", "--version"]).splitlines()[0] if output_of(["c++", "--version"]) else "",
    }


def load_average():
    try:
        return " ".join(open("/proc/loadavg").read().split()[:3])
    except OSError:
        return "?"


def git_state():
    commit = output_of(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"])
    status = output_of(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no", "--", "static_core",
                        "sim_io", "shading"])
    dirty = [line.split(maxsplit=1)[1] for line in status.splitlines() if line.strip()]
    return commit, dirty


def parse_name(name):
    """'frame/curtain/29929/threads:1/process_time/real_time_median' -> parts."""
    parts = name.split("/")
    family = parts[0]
    if family == "frame" and len(parts) > 2 and parts[1] == "real":  # frame/real/<sequence>/threads:1/...
        return "real", parts[2], 0, 1
    first = 2 if family == "stage" else 1  # stage/<stage>/<kind>/<vertices>/...
    kind = parts[first] if len(parts) > first else ""
    vertices = int(parts[first + 1]) if len(parts) > first + 1 and parts[first + 1].isdigit() else 0
    threads = 0
    for p in parts:
        m = re.match(r"threads:(\d+)", p)
        if m:
            threads = int(m.group(1))
    return family, kind, vertices, threads


def to_ms(value, unit):
    return value * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def collect(raw):
    """Medians (or the single run, when there was one repetition) keyed by run_name."""
    rows = {}
    for b in raw["benchmarks"]:
        run_name = b.get("run_name", b["name"])
        aggregate = b.get("aggregate_name", "")
        if b.get("run_type") == "aggregate" and aggregate not in ("median", "cv"):
            continue
        row = rows.setdefault(run_name, {"name": run_name})
        if aggregate == "cv":
            row["cv_real"] = b["real_time"]
            continue
        if b.get("run_type") == "iteration" and "real_ms" in row:
            continue  # a per-repetition row when aggregates exist: keep the first only as a fallback
        row["real_ms"] = to_ms(b["real_time"], b["time_unit"])
        row["cpu_ms"] = to_ms(b["cpu_time"], b["time_unit"])
        row["iterations"] = b.get("iterations", 0)
        row["repetitions"] = b.get("repetitions", 1)
        for key, value in b.items():
            if key not in ("name", "run_name", "run_type", "aggregate_name", "aggregate_unit", "real_time",
                           "cpu_time", "time_unit", "iterations", "repetitions", "repetition_index", "threads",
                           "family_index", "per_family_instance_index"):
                row[key] = value
    for row in rows.values():
        counted = row.get("vertices")  # the real rows count their vertices; their names do not carry it
        row["family"], row["kind"], row["vertices"], row["threads"] = parse_name(row["name"])
        if row["family"] == "real" and counted:
            row["vertices"] = int(counted)
    return rows


def fmt(value, digits=3):
    if value is None:
        return "–"
    if abs(value) >= 100:
        return f"{value:,.0f}"
    if abs(value) >= 10:
        return f"{value:.1f}"
    return f"{value:.{digits - 1}f}" if abs(value) >= 1 else f"{value:.{digits}f}"


def breakdown_table(stages, frames, allocations, vertices):
    md = []
    any_stage = stages[("slicing", vertices)]
    frame = frames.get(("curtain", vertices, 1))
    alloc = allocations.get(vertices)
    sv = any_stage.get("slice_vertices", 0)
    md.append(f"## Where the time goes: curtain, {vertices:,} vertices, one thread")
    md.append("")
    md.append(f"Each stage timed alone over the frame's whole slice set ({int(any_stage.get('slices', 0)):,} "
              f"slices, {int(sv):,} slice vertices), with warm per-thread scratch; \"rest\" is the frame "
              "(compute_visibility into a reused result, same process) minus the stages: storing each slice's cones on mesh "
              "vertices, the per-orientation fill (Dijkstra), the per-vertex cone lists, result vectors. "
              "Stages run back to back over all slices, so their caches differ from the "
              "interleaved frame. Allocations: operator-new calls per slice vertex (second pass, warm scratch).")
    md.append("")
    md.append("| stage | ms | CPU ms | µs / slice vertex (CPU) | % of frame (CPU) | % of frame (wall) | "
              "allocations / slice vertex |")
    md.append("|---|---:|---:|---:|---:|---:|---:|")
    total_real = total_cpu = 0.0
    for name in STAGES:
        r = stages.get((name, vertices))
        if not r:
            continue
        total_real += r["real_ms"]
        total_cpu += r["cpu_ms"]
        allocs = alloc.get(f"allocs_per_sv_{name}") if alloc else None
        md.append(f"| {STAGE_TEXT[name]} | {fmt(r['real_ms'])} | {fmt(r['cpu_ms'])} | "
                  f"{fmt(1e3 * r['cpu_ms'] / sv)} | "
                  f"{fmt(100 * r['cpu_ms'] / frame['cpu_ms']) if frame else '–'} | "
                  f"{fmt(100 * r['real_ms'] / frame['real_ms']) if frame else '–'} | {fmt(allocs)} |")
    if frame:
        rest_cpu, rest_real = frame["cpu_ms"] - total_cpu, frame["real_ms"] - total_real
        allocs_frame = alloc.get("allocs_per_sv_frame") if alloc else None
        allocs_rest = (allocs_frame - sum(alloc.get(f"allocs_per_sv_{n}", 0) for n in STAGES) if alloc else None)
        if rest_cpu >= 0:
            md.append(f"| rest (store, fill, bookkeeping) | {fmt(rest_real)} | {fmt(rest_cpu)} | "
                      f"{fmt(1e3 * rest_cpu / sv)} | {fmt(100 * rest_cpu / frame['cpu_ms'])} | "
                      f"{fmt(100 * rest_real / frame['real_ms'])} | {fmt(allocs_rest)} |")
        else:  # the stages alone are not additive (see the note below the table)
            md.append(f"| rest (store, fill, bookkeeping) | – ‡ | – ‡ | – ‡ | – ‡ | – ‡ | {fmt(allocs_rest)} |")
        md.append(f"| **whole frame** (compute_visibility into a reused result) | {fmt(frame['real_ms'])} | "
                  f"{fmt(frame['cpu_ms'])} | {fmt(1e3 * frame['cpu_ms'] / sv)} | 100 | 100 | {fmt(allocs_frame)} |")
        if alloc and "allocs_per_sv_frame_one_shot" in alloc:
            md.append(f"| whole frame, one-shot (fresh FrameVisibility) | | | | | | "
                      f"{fmt(alloc['allocs_per_sv_frame_one_shot'])} |")
    if frame and frame["cpu_ms"] < total_cpu:
        md.append("")
        md.append(f"‡ The stages timed alone sum to {fmt(1e3 * total_cpu / sv)} µs per slice vertex, more than the whole "
                  f"frame's {fmt(1e3 * frame['cpu_ms'] / sv)}, so the rest cannot be measured by subtraction here. They are not "
                  "additive: alone, each stage walks every slice's data (all triangulations, all cones) rather than one "
                  "slice at a time, and the 3D stage calls assemble_cone and measure_cone where the frame calls the "
                  "fused assemble_and_measure_cone. The stages' shares are comparable with each other.")
    md.append("")
    md.append("Issue 3 asks for no allocation per slice vertex in the hot path; the last column counts them "
              "(this binary replaces the global operator new; TBB's own allocator is not counted).")
    md.append("")
    return md


def write_plot(frames, stages, real, info, path):
    """static_core.png: µs of CPU per slice vertex against cloth size, one thread; left, the whole frame of each
    kind (and the real sequences' last frames) against the issue's targets; right, the curtain's stages.
    Returns False (and writes nothing) when this Python has no matplotlib (Debian: python3-matplotlib)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    markers = {"curtain": "o", "roll": "s", "flag": "^", "sleeve": "D"}
    for kind in sorted({k for (k, _, t) in frames if t == 1}):
        points = sorted((v, us_per_slice_vertex(r)) for (k, v, t), r in frames.items()
                        if k == kind and t == 1 and r.get("slice_vertices"))
        left.plot([p[0] for p in points], [p[1] for p in points], marker=markers.get(kind, "o"), label=kind)
    for (name, r), marker in zip(sorted(real.items()), "xP*+v<>"):
        if r.get("slice_vertices") and r.get("vertices"):
            left.scatter([r["vertices"]], [us_per_slice_vertex(r)], marker=marker, color="black",
                         label=f"{name} (real)")
    left.hlines(TARGET_US_PER_SLICE_VERTEX, 2000, LARGE_VERTICES, colors="gray", linestyles="--",
                label=f"target {TARGET_US_PER_SLICE_VERTEX:g} µs (2 µs at 300k)")
    left.hlines(TARGET_US_PER_SLICE_VERTEX_LARGE, LARGE_VERTICES, 400000, colors="gray", linestyles="--")
    left.set_title("whole frame (real Blender sequences: their last frame)", fontsize=9)
    for name in STAGES:
        points = sorted((v, 1e3 * r["cpu_ms"] / stages[("slicing", v)]["slice_vertices"])
                        for (n, v), r in stages.items() if n == name and ("slicing", v) in stages)
        right.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=STAGE_TEXT[name].split(" (")[0])
    right.set_title("curtain, each stage timed alone over the frame's slices", fontsize=9)
    for ax in (left, right):
        ax.set_xscale("log")
        ax.set_xlabel("mesh vertices")
        ax.set_ylabel("µs of CPU per slice vertex, one thread")
        ax.set_ylim(bottom=0)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"pleat static core, default plan: commit {info['commit']}, {info['machine']['model']}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def write_outputs(rows, info, out_dir, command_line, elapsed):
    os.makedirs(out_dir, exist_ok=True)
    frames = {(r["kind"], r["vertices"], r["threads"]): r for r in rows.values() if r["family"] == "frame"}
    rays = {(r["kind"], r["vertices"], r["threads"]): r for r in rows.values() if r["family"] == "embree_256"}
    stages = {(r["name"].split("/")[1], r["vertices"]): r for r in rows.values() if r["family"] == "stage"}
    allocations = {r["vertices"]: r for r in rows.values() if r["family"] == "allocations"}

    # CSV: one line per benchmark, medians.
    with open(os.path.join(out_dir, "static_core.csv"), "w", newline="") as f:
        fields = ["name", "family", "kind", "vertices", "threads", "real_ms", "cpu_ms", "cv_real", "iterations",
                  "repetitions", "slices", "slice_vertices", "us_per_slice_vertex_real", "us_per_slice_vertex_cpu",
                  "rays_cast", "rays_per_s"]
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for r in sorted(rows.values(), key=lambda r: r["name"]):
            line = dict(r)
            if r.get("slice_vertices"):
                line["us_per_slice_vertex_real"] = 1e3 * r["real_ms"] / r["slice_vertices"]
                line["us_per_slice_vertex_cpu"] = 1e3 * r["cpu_ms"] / r["slice_vertices"]
            writer.writerow(line)

    md = []
    md.append("# Static core speed (generated by bench/run_static_core_bench.py)")
    md.append("")
    md.append(f"Run {info['date']} on commit `{info['commit']}`"
              + (" plus uncommitted changes to " + ", ".join(f"`{d}`" for d in info["dirty"]) if info["dirty"] else "")
              + f"; {elapsed:.0f} s in all. Reproduce: `{command_line}`.")
    md.append("")
    md.append(f"- Machine: {info['machine']['model']}, `nproc` = {info['machine']['nproc']}, Linux "
              f"{info['machine']['kernel']}, {info['machine']['compiler']}, Release (-O3), Debian libbenchmark.")
    md.append(f"- **Shared machine**: load average {info['load_before']} before the run, {info['load_after']} after "
              "(1/5/15 min). Other jobs compete for the 2 cores, so wall-clock times (\"ms\") include waiting; the "
              "process CPU time (\"CPU ms\", all threads) is the cost a dedicated core would see. Two-thread "
              "speed-ups are limited by whatever else ran.")
    md.append("- Input: generated cloth (`ClothGenerator`, seed 0), frame 12 of 48 (a quarter of the cycle, halfway "
              "between rest and the deepest folds), the default diffuse plan (`make_diffuse_plan` with "
              "`DiffusePlanParams{}`: 8 orientations spread and relaxed, planes 1/2 of an average edge apart, "
              "interpolated-on-fan storage); the real sequences: their last, most folded sample, same plan.")
    md.append("- Threads: 1 = `params.parallel = false` under `tbb::global_control(max_allowed_parallelism, 1)`; "
              "2 = TBB over slices (and over vertices for the 3D assembly) under a control of 2. Embree: the same "
              "controls, `RayVisibilityParams::parallel` likewise.")
    md.append("- Medians of the repetitions shown; cv = coefficient of variation of the wall-clock time.")
    md.append("")

    md.append("## Per frame")
    md.append("")
    md.append("| cloth | vertices | slices | slice vertices | threads | ms / frame | cv | CPU ms | CPU ÷ wall | µs / slice vertex "
              "(wall) | µs / slice vertex (CPU) | paper 410 µs ÷ this (CPU) | vs target (CPU; 1.5 µs, 2 at 300k) | speed-up 2T/1T "
              "(wall) | CPU 2T ÷ 1T | Embree 256 rays ms | pleat ÷ Embree (wall) |")
    md.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for key in sorted(frames, key=lambda k: (k[0], k[1], k[2])):
        r = frames[key]
        kind, vertices, threads = key
        sv = r.get("slice_vertices", 0)
        us_real = 1e3 * r["real_ms"] / sv if sv else None
        us_cpu = 1e3 * r["cpu_ms"] / sv if sv else None
        base = frames.get((kind, vertices, 1))
        speedup = base["real_ms"] / r["real_ms"] if base and threads != 1 else None
        cpu_ratio = r["cpu_ms"] / base["cpu_ms"] if base and threads != 1 else None
        # Two threads that together got less than 1.5 cores: another job held the second core.
        busy = threads > 1 and r["cpu_ms"] / r["real_ms"] < 1.5
        ray = rays.get(key)
        md.append(
            f"| {kind} | {vertices:,} | {int(r.get('slices', 0)):,} | {int(sv):,} | {threads} | {fmt(r['real_ms'])} | "
            f"{fmt(100 * r['cv_real'], 2) + ' %' if 'cv_real' in r else '–'} | {fmt(r['cpu_ms'])} | "
            f"{fmt(r['cpu_ms'] / r['real_ms'])} | {fmt(us_real)} | "
            f"{fmt(us_cpu)} | {fmt(PAPER_US_PER_SLICE_VERTEX / us_cpu) + '×' if us_cpu else '–'} | "
            f"{fmt(us_cpu / target_for(vertices)) + '× the target' if us_cpu else '–'} | "
            f"{(fmt(speedup) + '×' + (' †' if busy else '')) if speedup else '–'} | {fmt(cpu_ratio)} | "
            f"{fmt(ray['real_ms']) if ray else '–'} | "
            f"{fmt(r['real_ms'] / ray['real_ms']) if ray else '–'} |")
    md.append("")
    md.append("† The two threads together got less than 1.5 cores (CPU ÷ wall): another job held the second core "
              "for most of that measurement, so this speed-up says nothing about the parallel path. \"CPU 2T ÷ 1T\" "
              "(the extra work of the parallel path) is unaffected.")
    md.append("")
    real = {r["kind"]: r for r in rows.values() if r["family"] == "real"}
    if real:
        md.append("## Real Blender sequences (last, most folded sample; one thread)")
        md.append("")
        md.append("The issue's bound: no real sequence above "
                  f"{fmt(REAL_BOUND, 2)}× the drape's CPU µs per slice vertex, and {fmt(TARGET_US_PER_SLICE_VERTEX, 2)} µs "
                  "per slice vertex on every one.")
        md.append("")
        md.append("| sequence | vertices | slices | slice vertices | ms / frame | cv | CPU ms | µs / slice vertex (CPU) | "
                  f"÷ drape | vs {fmt(TARGET_US_PER_SLICE_VERTEX, 2)} µs target |")
        md.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        drape_us = us_per_slice_vertex(real["drape"]) if "drape" in real else None
        for name in sorted(real, key=lambda n: (n != "drape", n)):
            r = real[name]
            us = us_per_slice_vertex(r)
            md.append(f"| {name} | {int(r.get('vertices', 0)):,} | {int(r.get('slices', 0)):,} | "
                      f"{int(r.get('slice_vertices', 0)):,} | "
                      f"{fmt(r['real_ms'])} | {fmt(100 * r['cv_real'], 2) + ' %' if 'cv_real' in r else '–'} | "
                      f"{fmt(r['cpu_ms'])} | {fmt(us)} | {fmt(us / drape_us) + '×' if us and drape_us else '–'} | "
                      f"{fmt(us / TARGET_US_PER_SLICE_VERTEX) + '×' if us else '–'} |")
        md.append("")
    md.append("Embree rows in detail (normals + BVH build + 256 cosine-distributed rays per vertex and side, "
              "both sides):")
    md.append("")
    md.append("| cloth | vertices | threads | ms / frame | cv | CPU ms | rays cast | Mrays/s (wall) | speed-up 2T/1T |")
    md.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for key in sorted(rays):
        r = rays[key]
        base = rays.get((key[0], key[1], 1))
        speedup = base["real_ms"] / r["real_ms"] if base and key[2] != 1 else None
        busy = key[2] > 1 and r["cpu_ms"] / r["real_ms"] < 1.5
        md.append(f"| {key[0]} | {key[1]:,} | {key[2]} | {fmt(r['real_ms'])} | "
                  f"{fmt(100 * r['cv_real'], 2) + ' %' if 'cv_real' in r else '–'} | {fmt(r['cpu_ms'])} | "
                  f"{int(r.get('rays_cast', 0)):,} | {fmt(r.get('rays_per_s', 0) / 1e6)} | "
                  f"{(fmt(speedup) + '×' + (' †' if busy else '')) if speedup else '–'} |")
    md.append("")

    sizes = sorted({v for (_, v) in stages})
    detail = 29929 if 29929 in sizes else (sizes[len(sizes) // 2] if sizes else None)
    if detail is not None:
        md.extend(breakdown_table(stages, frames, allocations, detail))
    if len(sizes) > 1:
        md.append("Growth with size (curtain, one thread, CPU time; each stage over its frame's whole slice set):")
        md.append("")
        md.append("| stage | " + " | ".join(f"µs / slice vertex at {v:,}" for v in sizes) + " | "
                  + " | ".join(f"% of frame at {v:,}" for v in sizes) + " |")
        md.append("|---|" + "---:|" * (2 * len(sizes)))
        for name in STAGES + ["rest", "frame"]:
            cells, shares = [], []
            for v in sizes:
                sv = stages.get(("slicing", v), {}).get("slice_vertices")
                frame = frames.get(("curtain", v, 1))
                if name == "frame":
                    cpu = frame["cpu_ms"] if frame else None
                elif name == "rest":
                    parts = [stages.get((n, v)) for n in STAGES]
                    cpu = frame["cpu_ms"] - sum(p["cpu_ms"] for p in parts) if frame and all(parts) else None
                else:
                    cpu = stages[(name, v)]["cpu_ms"] if (name, v) in stages else None
                if name == "rest" and cpu is not None and cpu < 0:  # not additive: see the note above
                    cells.append("– ‡")
                    shares.append("– ‡")
                    continue
                cells.append(fmt(1e3 * cpu / sv) if cpu is not None and sv else "–")
                shares.append(fmt(100 * cpu / frame["cpu_ms"]) if cpu is not None and frame else "–")
            label = {"rest": "rest (store, fill, bookkeeping)", "frame": "**whole frame**"}.get(
                name, STAGE_TEXT.get(name))
            md.append(f"| {label} | " + " | ".join(cells) + " | " + " | ".join(shares) + " |")
        md.append("")

    plot = os.path.join(out_dir, "static_core.png")
    if write_plot(frames, stages, real, info, plot):
        md.insert(2, "![µs per slice vertex against size, whole frame and stages](static_core.png)\n")
    else:
        print("run_static_core_bench: no matplotlib in this Python, static_core.png not written "
              "(Debian: python3-matplotlib, in /usr/bin/python3)", file=sys.stderr)
    with open(os.path.join(out_dir, "static_core.md"), "w") as f:
        f.write("\n".join(md))
    print("\n".join(md))


def run_under_python_with_matplotlib():
    """Re-runs this script under Debian's python3 when the python3 on PATH (a pyenv or venv) lacks matplotlib and
    Debian's has it, so that static_core.png is drawn in the same run."""
    try:
        import matplotlib  # noqa: F401
        return
    except ImportError:
        pass
    system = "/usr/bin/python3"
    if not os.path.exists(system) or os.path.realpath(sys.executable) == os.path.realpath(system):
        return
    if subprocess.run([system, "-c", "import matplotlib"], capture_output=True).returncode == 0:
        os.execv(system, [system, os.path.abspath(__file__)] + sys.argv[1:])


def main():
    run_under_python_with_matplotlib()
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build-dir", default=os.path.join(ROOT, "build-bench"))
    parser.add_argument("--out-dir", default=os.path.join(ROOT, "bench", "results"))
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--large-repetitions", type=int, default=2, help="repetitions at 300k vertices")
    parser.add_argument("--resolutions", default="55,173,548")
    parser.add_argument("--kinds", default="curtain,roll")
    parser.add_argument("--stage-resolutions", default="55,173,548")
    parser.add_argument("--wait-for-load", type=float, default=0.0,
                        help="before running, wait (at most --wait-max s) until the 1-min load average is below this")
    parser.add_argument("--wait-max", type=float, default=600.0)
    parser.add_argument("--no-build", action="store_true")
    parser.add_argument("--report-only", action="store_true",
                        help="rewrite the markdown and CSV from the last run's JSON files (no build, no run)")
    parser.add_argument("--quick", action="store_true", help="3k vertices, one repetition (end-to-end check)")
    args = parser.parse_args()
    if args.quick:
        args.resolutions, args.stage_resolutions, args.repetitions = "55", "55", 1

    json_path = os.path.join(args.out_dir, "static_core.json")
    run_path = os.path.join(args.out_dir, "static_core_run.json")
    if args.report_only:
        with open(json_path) as f:
            raw = json.load(f)
        with open(run_path) as f:
            info = json.load(f)
        write_outputs(collect(raw), info, args.out_dir, info["command_line"], info["elapsed"])
        return

    started = time.time()
    if not args.no_build:
        run(["cmake", "-S", ROOT, "-B", args.build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DPLEAT_BUILD_TESTS=OFF"],
            stdout=subprocess.DEVNULL)
        run(["cmake", "--build", args.build_dir, "-j2", "--target", "static_core_bench"], stdout=subprocess.DEVNULL)
    binary = os.path.join(args.build_dir, "bench", "static_core_bench")
    os.makedirs(args.out_dir, exist_ok=True)
    if args.wait_for_load > 0:
        deadline = time.time() + args.wait_max
        while float(load_average().split()[0]) >= args.wait_for_load and time.time() < deadline:
            time.sleep(10)
    info = {"machine": machine(), "load_before": load_average(),
            "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")}
    info["commit"], info["dirty"] = git_state()
    run([binary, f"--pleat_resolutions={args.resolutions}", f"--pleat_kinds={args.kinds}",
         f"--pleat_large_repetitions={args.large_repetitions}", f"--pleat_stage_resolutions={args.stage_resolutions}",
         f"--benchmark_repetitions={args.repetitions}", "--benchmark_report_aggregates_only=true",
         "--benchmark_min_time=0.5", f"--benchmark_out={json_path}", "--benchmark_out_format=json"],
        stdout=sys.stderr)
    info["load_after"] = load_average()
    with open(json_path) as f:
        raw = json.load(f)
    info["command_line"] = "bench/run_static_core_bench.py" + (" --quick" if args.quick else "")
    info["elapsed"] = time.time() - started
    with open(run_path, "w") as f:
        json.dump(info, f, indent=1)
    write_outputs(collect(raw), info, args.out_dir, info["command_line"], info["elapsed"])


if __name__ == "__main__":
    main()
