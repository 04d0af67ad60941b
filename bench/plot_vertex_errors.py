#!/usr/bin/env python3
"""Where the cones' error is: a breakdown and a picture of frame_coherence_bench --vertex-errors.

Reads frame_coherence_errors_<sequence>_<vertices>.csv files (frame, vertex, side, x, y, z, static, reference)
and writes, per file, a Markdown breakdown of e = A_static - A_reference (mean |e|, bias and share of the total
|e| by side and by the reference's value; the share held by the worst fifth of values) and a PNG of the last
frame's vertices coloured by e, each side seen along the three axes. Prints the Markdown too.

  python3 bench/plot_vertex_errors.py bench/results/frame_coherence_errors_*.csv [--out DIR]

Debian's python3-numpy and python3-matplotlib (scripts/setup.sh installs them).
"""
import argparse
import os
import sys

import numpy as np

BINS = [0.0, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 1.0 + 1e-9]


def load(path):
    data = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    if data.size == 0:
        sys.exit(f"plot_vertex_errors: {path}: no rows")
    return data


def breakdown(name, d):
    e = d["static"] - d["reference"]
    total = np.abs(e).sum()
    share = lambda m: np.abs(e[m]).sum() / total if total > 0 else 0.0
    lines = [f"### {name}", "",
             f"{e.size} values, frames {d['frame'].min()}–{d['frame'].max()}: mean |e| {np.abs(e).mean():.4f}, "
             f"bias {e.mean():+.4f}, p95 {np.percentile(np.abs(e), 95):.4f}; the worst fifth of the values holds "
             f"{np.sort(np.abs(e))[::-1][: max(1, e.size // 5)].sum() / max(total, 1e-300):.0%} of the total |e|.",
             "", "| values | count | mean A_ref | mean abs(e) | bias | share of abs(e) |", "|---|---|---|---|---|---|"]
    for side in ("front", "back"):
        m = d["side"] == side
        if m.any():
            lines.append(f"| {side} side | {m.sum()} | {d['reference'][m].mean():.3f} | {np.abs(e[m]).mean():.4f} | "
                         f"{e[m].mean():+.4f} | {share(m):.0%} |")
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        m = (d["reference"] >= lo) & (d["reference"] < hi)
        if m.any():
            lines.append(f"| A_ref in [{lo:g}, {min(hi, 1.0):g}{']' if hi > 1 else ')'} | {m.sum()} | "
                         f"{d['reference'][m].mean():.3f} | {np.abs(e[m]).mean():.4f} | {e[m].mean():+.4f} | "
                         f"{share(m):.0%} |")
    return "\n".join(lines) + "\n"


def picture(name, d, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    last = d[d["frame"] == d["frame"].max()]
    e = last["static"] - last["reference"]
    limit = max(0.02, float(np.percentile(np.abs(e), 98)))
    fig, axes = plt.subplots(2, 3, figsize=(15, 9), constrained_layout=True)
    views = [("x", "y"), ("x", "z"), ("z", "y")]
    for row, side in enumerate(("front", "back")):
        m = last["side"] == side
        for col, (h, v) in enumerate(views):
            ax = axes[row][col]
            order = np.argsort(np.abs(e[m]))  # the largest errors drawn last, on top
            dots = ax.scatter(last[h][m][order], last[v][m][order], c=e[m][order], cmap="RdBu", vmin=-limit,
                              vmax=limit, s=5)
            ax.set_aspect("equal")
            ax.set_title(f"{side} side, {h}–{v}")
    fig.colorbar(dots, ax=axes, shrink=0.8, label="A_static − A_reference (red: too dark)")
    fig.suptitle(f"{name}: error per vertex, frame {last['frame'][0]}")
    fig.savefig(png, dpi=80)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--out", help="directory of the .md and .png (default: beside each file)")
    args = parser.parse_args()
    for path in args.files:
        if not os.path.isfile(path):
            sys.exit(f"plot_vertex_errors: {path}: no such file")
        name = os.path.basename(path)[: -len(".csv")]
        d = load(path)
        out_dir = args.out or os.path.dirname(path) or "."
        os.makedirs(out_dir, exist_ok=True)
        text = breakdown(name, d)
        with open(os.path.join(out_dir, name + ".md"), "w") as f:
            f.write(text)
        picture(name, d, os.path.join(out_dir, name + ".png"))
        print(text)
        print(f"plot_vertex_errors: wrote {os.path.join(out_dir, name)}.md and .png")


if __name__ == "__main__":
    main()
