#!/usr/bin/env python3
"""Plots the coherence cases (bench/coherence_cases_bench.cpp): kinetic ÷ static per frame against the share of
the cloth's vertices that moved, one point per case and sequence, with the targets of each case.

Usage: bench/plot_coherence_cases.py DIR/frame_coherence_cases.csv --out DIR  (writes DIR/frame_coherence_cases.png)
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Targets (kinetic ÷ static, one thread, medians) per case.
TARGETS = {"still": 0.03, "patch1": 0.1, "patch10": 0.35, "u8": 0.5, "u4": 0.7, "u1": 1.0}
MARKERS = {"still": "o", "corner": "^", "patch1": "s", "patch10": "D", "patch50": "P", "u1": "x", "u4": "v", "u8": "<"}
HELD = 1e-4  # where a held frame (nothing moved) is drawn on the log axis


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("csv")
    parser.add_argument("--out", default=".")
    args = parser.parse_args()
    with open(args.csv) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit("plot_coherence_cases: no rows in " + args.csv)
    sequences = sorted({r["sequence"] for r in rows})
    colours = {s: plt.cm.tab10(i) for i, s in enumerate(sequences)}
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    for r in rows:
        x = max(float(r["moved_fraction"]), HELD)
        y = float(r["ratio"])
        ax.scatter(x, y, marker=MARKERS.get(r["case"], "o"), color=colours[r["sequence"]], s=46, zorder=3)
    for case, target in TARGETS.items():
        xs = [max(float(r["moved_fraction"]), HELD) for r in rows if r["case"] == case]
        if xs:
            ax.hlines(target, min(xs) / 1.6, max(xs) * 1.6, colors="grey", linestyles="dashed", linewidth=1)
            ax.annotate("target " + case, (max(xs) * 1.7, target), fontsize=7, color="grey", va="center")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axvline(HELD * 1.8, color="lightgrey", linewidth=0.8)
    ax.set_xlabel("share of the cloth's vertices that moved in the frame (held frames drawn at 1e-4)")
    ax.set_ylabel("kinetic ÷ static, per frame (median)")
    ax.set_title("What a frame costs the kinetic engine: one thread, same run")
    for case, m in MARKERS.items():
        if any(r["case"] == case for r in rows):
            ax.scatter([], [], marker=m, color="black", label=case)
    for s in sequences:
        ax.scatter([], [], marker="s", color=colours[s], label=s)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    ax.grid(True, which="both", alpha=0.25)
    fig.tight_layout()
    out = os.path.join(args.out, "frame_coherence_cases.png")
    fig.savefig(out, dpi=120)
    print("plot_coherence_cases: wrote " + out)


if __name__ == "__main__":
    main()
