#!/usr/bin/env python3
"""Plots of the frame-coherence benchmark (bench/frame_coherence_bench.cpp) from its CSV.

Usage: bench/plot_frame_coherence.py [CSV] [--out DIR] [--plots NAME,...]
  CSV   default bench/results/frame_coherence.csv
  DIR   default: the CSV's directory
  NAME  time-vs-upsample, ratio, error-vs-time, flicker-vs-time, scaling, error-cost (default: all; each is
        skipped when the CSV lacks its rows)

Writes (PNG, one panel per sequence):
  frame_coherence_time_vs_upsample.png  ms/frame against temporal resolution u, per method (one row per size)
  frame_coherence_ratio.png             kinetic / static time per frame against u, per sequence and size
  frame_coherence_error_vs_time.png     mean |A - A_ref| against ms/frame at u = 1, one thread: Embree's ray
                                        ladder as a curve, the cone engines as points (speed at matched accuracy)
  frame_coherence_flicker_vs_time.png   the same for temporal flicker
  frame_coherence_scaling.png           ms/frame against vertices, log-log, per method (u = 1), with slopes
  frame_coherence_error_cost.png        with --plans rows (bench/run_error_cost.sh): mean and p95 error against
                                        CPU ms/frame of each plan of the static engine beside Embree's ladder
Every plot uses the one-thread rows.
Needs matplotlib (Debian: python3-matplotlib).
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402

METHOD_STYLE = {
    "static": dict(color="#1f77b4", marker="s", label="static engine"),
    "kinetic": dict(color="#d62728", marker="o", label="kinetic engine"),
    "paper": dict(color="#ff7f0e", marker="D", label="static engine, the paper's plan"),
    "embree": dict(color="#555555", marker="v", label="Embree (ray ladder)"),
    "embree-random": dict(color="#2ca02c", marker="x", label="Embree, new directions each frame"),
}
SCALING_RAYS = 32  # Embree's ray count in the scaling plot
SEQUENCE_ORDER = ["drape", "pile", "rucked", "curtain", "roll", "flag", "sleeve"]


def number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return math.nan
    return value


def load(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("status", "ok") != "ok" or r.get("threads", "1") != "1":
                continue
            r["vertices"] = int(r["vertices"])
            r["rays"] = int(r["rays"])
            r["upsample"] = number(r["upsample"])
            for key in ("ms_per_frame", "cpu_ms_per_frame", "mean_err", "p95_err", "flicker"):
                r[key] = number(r[key])
            rows.append(r)
    return rows


def ordered(names):
    return sorted(names, key=lambda s: (SEQUENCE_ORDER.index(s) if s in SEQUENCE_ORDER else 99, s))


def u_label(u):
    return f"{u:g}"


def log_y(ax):
    """Log y axis with plain-number labels at 1, 2, 5 x 10^k (a decade or less shows several labels)."""
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(ticker.NullFormatter())


def log_x(ax):
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(ticker.NullFormatter())


def save(fig, path, title, legend_axes=None, legend_cols=None):
    """Title, an optional legend gathered from all panels below them, tight layout, PNG."""
    bottom = 0.0
    if legend_axes is not None:
        handles, labels = [], []
        for ax in legend_axes:
            for h, l in zip(*ax.get_legend_handles_labels()):
                if l not in labels:
                    handles.append(h)
                    labels.append(l)
        ncol = min(len(labels), legend_cols or 4)
        legend_rows = math.ceil(len(labels) / max(1, ncol))
        height = fig.get_size_inches()[1]
        bottom = min(0.3, (0.32 * legend_rows + 0.15) / height)
        fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=10, frameon=False)
    top = 1 - 0.5 / fig.get_size_inches()[1]
    fig.suptitle(title, fontsize=14)
    fig.tight_layout(rect=(0, bottom, 1, top))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"plot_frame_coherence: wrote {path}")


def panel_grid(count, rows=1, width=4.2, height=3.8, min_width=10.0):
    cols = max(1, count)
    width = max(width, min_width / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows + 1.3), squeeze=False)
    return fig, axes


def plot_time_vs_upsample(rows, out):
    sequences = ordered({r["sequence"] for r in rows})
    sizes = sorted({r["vertices"] for r in rows if r["source"] == "generated"}) or [0]
    fig, axes = panel_grid(len(sequences), rows=len(sizes))
    for i, size in enumerate(sizes):
        for j, seq in enumerate(sequences):
            ax = axes[i][j]
            sel = [r for r in rows if r["sequence"] == seq and (r["source"] != "generated" or r["vertices"] == size)]
            if not sel or (i > 0 and sel[0]["source"] != "generated"):
                ax.axis("off")
                continue
            for method in ("static", "kinetic"):
                pts = sorted((r["upsample"], r["ms_per_frame"]) for r in sel if r["method"] == method)
                if not pts:
                    continue
                st = METHOD_STYLE[method]
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=st["marker"], color=st["color"],
                        label=st["label"], linewidth=1.5, markersize=5)
            ax.set_xscale("log", base=2)
            log_y(ax)
            us = sorted({r["upsample"] for r in sel})
            ax.set_xticks(us)
            ax.set_xticklabels([u_label(u) for u in us])
            ax.set_title(f"{seq}, {sel[0]['vertices']:,} vertices", fontsize=11)
            ax.set_xlabel("temporal resolution u (frames per native frame)")
            if j == 0:
                ax.set_ylabel("wall ms per frame")
            ax.grid(True, which="both", alpha=0.3)
    save(fig, os.path.join(out, "frame_coherence_time_vs_upsample.png"),
         "Time per frame against temporal resolution (higher u: smaller motion per frame)", axes.flat, 5)


def plot_ratio(rows, out):
    by = defaultdict(dict)
    for r in rows:
        if r["method"] in ("static", "kinetic"):
            by[(r["sequence"], r["vertices"], r["upsample"])][r["method"]] = r["ms_per_frame"]
    series = defaultdict(list)
    for (seq, n, u), d in by.items():
        if "static" in d and "kinetic" in d and d["static"] > 0:
            series[(seq, n)].append((u, d["kinetic"] / d["static"]))
    fig, ax = plt.subplots(figsize=(9.5, 6))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    seqs = ordered({s for s, _ in series})
    sizes = sorted({n for _, n in series})
    for (seq, n), pts in sorted(series.items(), key=lambda kv: (seqs.index(kv[0][0]), kv[0][1])):
        pts.sort()
        small = n == min(m for s, m in series if s == seq)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "-" if small else "--", marker="o" if small else "s",
                color=colors[seqs.index(seq) % len(colors)], label=f"{seq}, {n:,} vertices")
    ax.axhline(1.0, color="black", linewidth=1)
    ax.set_xscale("log", base=2)
    us = sorted({p[0] for pts in series.values() for p in pts})
    ax.set_xticks(us)
    ax.set_xticklabels([u_label(u) for u in us])
    ax.set_xlabel("temporal resolution u (frames per native frame)")
    ax.set_ylabel("kinetic ms / static ms (same frames, interleaved)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=9, ncol=2)
    save(fig, os.path.join(out, "frame_coherence_ratio.png"),
         "Kinetic engine's time per frame ÷ the static engine's (< 1: kinetic is faster)")


def plot_accuracy_vs_time(rows, out, metric, label, filename, title):
    native = [r for r in rows if r["upsample"] == 1 and not math.isnan(r[metric])]
    sequences = ordered({r["sequence"] for r in native})
    if not sequences:
        return
    fig, axes = panel_grid(len(sequences))
    u_max = max(r["upsample"] for r in rows)
    for j, seq in enumerate(sequences):
        ax = axes[0][j]
        sel = [r for r in native if r["sequence"] == seq]
        sizes = sorted({r["vertices"] for r in sel})
        for k, n in enumerate(sizes):
            fill = "full" if k == 0 else "none"
            ladder = sorted((r["rays"], r["ms_per_frame"], r[metric]) for r in sel
                            if r["vertices"] == n and r["method"] == "embree")
            if ladder:
                st = METHOD_STYLE["embree"]
                ax.plot([p[1] for p in ladder], [p[2] for p in ladder], "-", marker=st["marker"], color=st["color"],
                        fillstyle=fill, linewidth=1, markersize=5, label=st["label"] if k == 0 else None)
                for rays, ms, value in ladder:
                    if rays in (8, 16, 32, 64, 256, 1024):
                        ax.annotate(f"{rays}", (ms, value), textcoords="offset points", xytext=(4, 3), fontsize=7,
                                    color="#555555")
            for method in ("static", "kinetic", "paper", "embree-random"):
                for r in sel:
                    if r["vertices"] == n and r["method"] == method:
                        st = METHOD_STYLE[method]
                        name = st["label"] + (f" ({r['rays']} rays)" if method == "embree-random" else " (u=1)")
                        ax.plot(r["ms_per_frame"], r[metric], st["marker"], color=st["color"], fillstyle=fill,
                                markersize=9, label=name if k == 0 else None)
            if len(sizes) > 1 and ladder:
                ax.annotate(f"{n:,} v", (ladder[0][1], ladder[0][2]), textcoords="offset points", xytext=(0, -14),
                            fontsize=8, ha="center")
        log_x(ax)
        log_y(ax)
        ax.set_title(seq + ("" if len(sizes) == 1 else ": filled " + f"{sizes[0]:,}" + ", hollow " +
                            ", ".join(f"{n:,}" for n in sizes[1:]) + " vertices"), fontsize=10)
        ax.set_xlabel("wall ms per frame, one thread")
        if j == 0:
            ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    save(fig, os.path.join(out, filename), title, axes.flat, 4)


def plot_scaling(rows, out):
    gen = [r for r in rows if r["source"] == "generated" and r["upsample"] == 1]
    sequences = ordered({r["sequence"] for r in gen})
    sizes = sorted({r["vertices"] for r in gen})
    if len(sizes) < 2:
        print("plot_frame_coherence: one size only, no scaling plot", file=sys.stderr)
        return
    fig, axes = panel_grid(len(sequences))
    for j, seq in enumerate(sequences):
        ax = axes[0][j]
        sel = [r for r in gen if r["sequence"] == seq]
        for method in ("static", "kinetic", "embree"):
            pts = sorted((r["vertices"], r["ms_per_frame"]) for r in sel
                         if r["method"] == method and (method != "embree" or r["rays"] == SCALING_RAYS))
            if len(pts) < 2:
                continue
            slope = math.log(pts[-1][1] / pts[0][1]) / math.log(pts[-1][0] / pts[0][0])
            st = METHOD_STYLE[method]
            name = f"Embree {SCALING_RAYS} rays" if method == "embree" else st["label"]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=st["marker"], color=st["color"],
                    label=f"{name}: slope {slope:.2f}")
        ax.set_xscale("log")
        log_y(ax)
        ax.set_xticks(sizes)
        ax.set_xticklabels([f"{n:,}" for n in sizes])
        ax.minorticks_off()
        ax.set_title(f"{seq}, u = 1", fontsize=11)
        ax.set_xlabel("vertices")
        if j == 0:
            ax.set_ylabel("wall ms per frame")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    save(fig, os.path.join(out, "frame_coherence_scaling.png"),
         "Time per frame against vertex count (log-log; slope 1 = linear)")


STORAGE_COLOR = {
    "nearer-endpoint": "#ff7f0e",
    "nearest-on-fan": "#9467bd",
    "interpolated-on-fan": "#2ca02c",
    "aimed-on-fan": "#1f77b4",
}
SPACING_MARKER = {0.5: "o", 0.75: "^", 1.0: "s"}
SPACING_LINE = {0.5: "-", 0.75: ":", 1.0: "--"}
LADDER_LABELS = (8, 16, 32, 64, 128, 256, 1024)


def parse_plan(name):
    """'12:0.5:aimed-on-fan[:spiral]' -> (orientations, spacing, storage, spiral)."""
    fields = name.split(":")
    return int(fields[0]), float(fields[1]), fields[2], len(fields) > 3


def plot_error_cost(rows, out):
    """Per real sequence (columns) and error measure (rows): Embree's ladder and every plan, CPU ms per frame."""
    plans = [r for r in rows if r["method"] == "plan" and r["upsample"] == 1 and not math.isnan(r["mean_err"])]
    sequences = ordered({r["sequence"] for r in plans})
    if not sequences:
        return
    metrics = (("mean_err", "mean |A − A_ref|"), ("p95_err", "95th percentile of |A − A_ref|"))
    fig, axes = panel_grid(len(sequences), rows=len(metrics), width=5.2, height=5.2)
    for i, (metric, label) in enumerate(metrics):
        for j, seq in enumerate(sequences):
            ax = axes[i][j]
            sel = [r for r in rows if r["sequence"] == seq and r["upsample"] == 1]
            ladder = sorted((r["rays"], r["cpu_ms_per_frame"], r[metric]) for r in sel if r["method"] == "embree")
            if ladder:
                ax.plot([p[1] for p in ladder], [p[2] for p in ladder], "-", marker="v", color="#555555",
                        linewidth=1.2, markersize=4, label="Embree, K rays per vertex")
                for rays, ms, value in ladder:
                    if rays in LADDER_LABELS:
                        ax.annotate(f"K={rays}", (ms, value), textcoords="offset points", xytext=(3, 3),
                                    fontsize=7, color="#555555")
            static = [r for r in sel if r["method"] == "static"]
            mine = [r for r in sel if r["method"] == "plan" and not math.isnan(r[metric])]
            # Spread orientations of one storage rule and spacing, joined in orientation order.
            families = defaultdict(list)
            for r in mine:
                o, spacing, storage, spiral = parse_plan(r["config"])
                if o != 6 and not spiral:
                    families[(storage, spacing)].append((o, r["cpu_ms_per_frame"], r[metric]))
            for (storage, spacing), pts in families.items():
                pts.sort()
                ax.plot([p[1] for p in pts], [p[2] for p in pts], SPACING_LINE.get(spacing, "-."),
                        color=STORAGE_COLOR.get(storage, "black"), linewidth=0.8, alpha=0.6)
            for r in mine:
                o, spacing, storage, spiral = parse_plan(r["config"])
                color = STORAGE_COLOR.get(storage, "black")
                marker = SPACING_MARKER.get(spacing, "^")
                ax.plot(r["cpu_ms_per_frame"], r[metric], marker, color=color, markersize=7,
                        fillstyle="none" if o == 6 else "full")
                # The plan that is the default repeats the static engine's row exactly.
                default = any(s["mean_err"] == r["mean_err"] and s["p95_err"] == r["p95_err"] for s in static)
                if default:
                    ax.plot(r["cpu_ms_per_frame"], r[metric], "*", color="black", markersize=16,
                            fillstyle="none", markeredgewidth=1.2, label="pleat's default plan")
                text = f"{o}" + (" axes" if o == 6 else "") + (" spiral" if spiral else "")
                if r["config"] == "6:1:nearer-endpoint":
                    text = "paper"
                ax.annotate(text, (r["cpu_ms_per_frame"], r[metric]), textcoords="offset points",
                            xytext=(5, -3), fontsize=7, color=color)
            log_x(ax)
            log_y(ax)
            # The plans' range of error (Embree's ladder runs on below it, off the panel).
            values = [r[metric] for r in mine] + [p[2] for p in ladder[:1]]
            if values:
                ax.set_ylim(min(r[metric] for r in mine) / 1.5 if mine else min(values) / 1.5, max(values) * 1.3)
            vertices = sel[0]["vertices"] if sel else 0
            ax.set_title(f"{seq}, {vertices:,} vertices", fontsize=11)
            ax.set_xlabel("CPU ms per frame, one thread")
            if j == 0:
                ax.set_ylabel(label)
            ax.grid(True, which="both", alpha=0.3)
    # Legend entries for the colours (storage rule) and the marker shapes (spacing).
    ax0 = axes[0][0]
    storages = {parse_plan(r["config"])[2] for r in plans}
    for storage, color in STORAGE_COLOR.items():
        if storage in storages:
            ax0.plot([], [], "o", color=color, label=f"storage {storage}")
    spacings = {parse_plan(r["config"])[1] for r in plans}
    for spacing, marker in SPACING_MARKER.items():
        if spacing not in spacings:
            continue
        ax0.plot([], [], marker, color="#777777", linestyle=SPACING_LINE[spacing],
                 label=f"planes {spacing:g} edge apart (line: 8 → 12 → 16 → 24 orientations)")
    ax0.plot([], [], "o", color="#777777", fillstyle="none", label="hollow: the paper's 6 axes")
    save(fig, os.path.join(out, "frame_coherence_error_cost.png"),
         "Error against cost: pleat's plans (labels: orientations) beside Embree's ray ladder (one thread, u = 1)",
         axes.flat, 3)


PLOTS = {
    "time-vs-upsample": plot_time_vs_upsample,
    "ratio": plot_ratio,
    "error-vs-time": lambda rows, out: plot_accuracy_vs_time(
        rows, out, "mean_err", "mean |A − A_ref| (4096 rays)", "frame_coherence_error_vs_time.png",
        "Mean error against time per frame (lower left is better; one thread, u = 1)"),
    "flicker-vs-time": lambda rows, out: plot_accuracy_vs_time(
        rows, out, "flicker", "flicker: mean |ΔA − ΔA_ref| between frames", "frame_coherence_flicker_vs_time.png",
        "Temporal flicker against time per frame (lower left is better; one thread, u = 1)"),
    "scaling": plot_scaling,
    "error-cost": plot_error_cost,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="?", default="bench/results/frame_coherence.csv")
    parser.add_argument("--out", default=None)
    parser.add_argument("--plots", default=",".join(PLOTS), help="comma-separated: " + ", ".join(PLOTS))
    args = parser.parse_args()
    chosen = [p for p in args.plots.split(",") if p]
    unknown = [p for p in chosen if p not in PLOTS]
    if unknown:
        sys.exit(f"plot_frame_coherence: unknown plot {', '.join(unknown)} (known: {', '.join(PLOTS)})")
    rows = load(args.csv)
    if not rows:
        sys.exit(f"plot_frame_coherence: no usable rows in {args.csv}")
    out = args.out or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out, exist_ok=True)
    for name in chosen:
        PLOTS[name](rows, out)


if __name__ == "__main__":
    main()
