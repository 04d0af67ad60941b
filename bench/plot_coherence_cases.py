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
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [2.2, 1]})
    # Left: the still cloth, the lifted corner and the patches, against the share that moved.
    partial = [r for r in rows if not r["case"].startswith("u")]
    for r in partial:
        left.scatter(max(float(r["moved_fraction"]), HELD), float(r["ratio"]), marker=MARKERS.get(r["case"], "o"),
                     color=colours[r["sequence"]], s=46, zorder=3, alpha=0.85)
    for case, target in TARGETS.items():
        xs = [max(float(r["moved_fraction"]), HELD) for r in partial if r["case"] == case]
        if xs:
            left.hlines(target, min(xs) / 2.2, max(xs) * 2.2, colors="grey", linestyles="dashed", linewidth=1)
            left.annotate("target " + case, (min(xs) / 2.1, target * 1.12), fontsize=7, color="grey")
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("share of the cloth's vertices that moved in the frame (held frames drawn at 1e-4)")
    left.set_ylabel("kinetic ÷ static, per frame (median)")
    left.set_title("Part of a settled cloth moving")
    for case, m in MARKERS.items():
        if any(r["case"] == case for r in partial):
            left.scatter([], [], marker=m, color="black", label=case)
    for s in sequences:
        left.scatter([], [], marker="s", color=colours[s], label=s)
    left.legend(fontsize=7, ncol=2, loc="lower right")
    left.grid(True, which="both", alpha=0.25)
    # Right: the sequences themselves (every vertex moves) against the frame rate.
    rates = [r for r in rows if r["case"].startswith("u")]
    for s in sequences:
        mine = sorted((float(r["case"][1:]), float(r["ratio"])) for r in rates if r["sequence"] == s)
        if mine:
            right.plot([u for u, _ in mine], [y for _, y in mine], "o-", color=colours[s], label=s)
    for case in ("u1", "u4", "u8"):
        u = float(case[1:])
        right.hlines(TARGETS[case], u / 1.25, u * 1.25, colors="grey", linestyles="dashed", linewidth=1)
        right.annotate("target", (u / 1.25, TARGETS[case] * 0.93), fontsize=7, color="grey", va="top")
    right.set_xscale("log", base=2)
    right.set_xticks([1, 4, 8], ["1×", "4×", "8×"])
    right.set_ylim(0.4, 1.2)
    right.set_xlabel("frame rate (× native; frames interpolated)")
    right.set_title("The sequences: every vertex moves")
    right.legend(fontsize=7)
    right.grid(True, which="both", alpha=0.25)
    fig.suptitle("What a frame costs the kinetic engine against the static one: one thread, same run")
    fig.tight_layout()
    out = os.path.join(args.out, "frame_coherence_cases.png")
    fig.savefig(out, dpi=110)
    print("plot_coherence_cases: wrote " + out)


if __name__ == "__main__":
    main()
