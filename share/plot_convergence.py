#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Plot of a vrsph JSON table (rows[] grouped by a column).

Usage: plot_convergence.py TABLE.json OUT.png --x dx --y error_inf --group method [--title T] [--linear]
Log-log (default): one line per group and reference slopes 1 and 2 (convergence).
--y may list several columns, one panel each, and give each its reference slopes after a
colon, separated by '/': --y seconds_total:1,solver_iterations:0 (cost O(N), flat
iteration count).
--linear: linear axes, no reference slopes (e.g. normalised vibration spectra).
Each method keeps one colour in every figure (a fixed palette by name). Where the rows carry
the spread over random seeds (columns Y_min and Y_max, with seeds > 1) it is drawn as a band
around the mean line.
"""
import argparse
import json
import sys
import zlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("table")
    ap.add_argument("png")
    ap.add_argument("--x", default="dx")
    ap.add_argument("--y", default="error_inf")
    ap.add_argument("--group", default="method")
    ap.add_argument("--title", default="")
    ap.add_argument("--linear", action="store_true")
    args = ap.parse_args()
    with open(args.table, encoding="utf-8") as f:
        rows = json.load(f)["rows"]
    panels = []
    for item in args.y.split(","):
        name, _, slopes = item.partition(":")
        panels.append((name, [float(p) for p in slopes.split("/")] if slopes else [1.0, 2.0]))
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.5), squeeze=False)
    for ax, (y, slopes) in zip(axes[0], panels):
        if not draw_panel(ax, rows, args, y, slopes):
            print(f"plot_convergence.py: nothing to plot for {y}", file=sys.stderr)
            return 1
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    return 0


# One colour per method in every figure: the registry's methods get fixed colours, other
# groups one from the same palette chosen by a hash of the name (stable across runs).
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
           "#bcbd22", "#17becf", "#393b79", "#637939", "#000000", "#ad494a", "#8c6d31", "#843c39", "#5254a3"]
# The registry's methods, then the benchmarks' configurations (`bench accuracy`).
FIXED = {name: PALETTE[k] for k, name in enumerate(
    ["vrsph", "sph", "fpm", "cspm", "kgf", "aar-sph", "chen-beraun", "rkpm1", "rkpm2", "mfpm", "fpm2o", "p1-fem",
     "fenicsx-p1", "fenicsx-p2", "fenicsx-p3", "vrsph-qw", "vrsph-point"])}
MARKERS = "osD^v<>ph*"


def style_of(name):
    if name in FIXED:
        k = list(FIXED).index(name)
        return FIXED[name], MARKERS[k % len(MARKERS)]
    h = zlib.crc32(name.encode())
    return PALETTE[h % len(PALETTE)], MARKERS[h % len(MARKERS)]


def draw_panel(ax, rows, args, y, slopes) -> bool:
    groups = {}
    for r in rows:
        if r.get(args.x) is None or r.get(y) is None or (not args.linear and r[y] <= 0):
            continue
        lo, hi = r.get(y + "_min"), r.get(y + "_max")
        spread = (lo, hi) if (r.get("seeds", 1) or 1) > 1 and lo is not None and hi is not None else None
        groups.setdefault(str(r.get(args.group, "")), []).append((r[args.x], r[y], spread))
    if not groups:
        return False
    xs_all = []
    for name, pts in sorted(groups.items()):
        pts.sort(key=lambda p: p[0])
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        xs_all += xs
        colour, marker = style_of(name)
        bands = [p for p in pts if p[2] is not None]
        label = name + (f" (min-max over {max(r.get('seeds', 1) for r in rows)} seeds)" if bands else "")
        if args.linear:
            ax.plot(xs, ys, marker=marker, markersize=3, color=colour, label=label)
        else:
            ax.loglog(xs, ys, marker=marker, color=colour, label=label)
        if len(bands) > 1:
            ax.fill_between([p[0] for p in bands], [p[2][0] for p in bands], [p[2][1] for p in bands],
                            color=colour, alpha=0.2, linewidth=0)
    if not args.linear:
        # Reference slopes anchored at the smallest x of the first group.
        x0, x1 = min(xs_all), max(xs_all)
        first = groups[sorted(groups)[0]]
        y0 = min(p[1] for p in first)
        for p, style in zip(slopes, (":", "--", "-.", ":")):
            ax.loglog([x0, x1], [y0, y0 * (x1 / x0) ** p], "k" + style, linewidth=0.8, label=f"slope {p:g}")
        # A nearly flat series (iteration counts) on a log axis: show a factor-of-4 window,
        # or the flat line looks like a slope.
        ys_all = [p[1] for pts in groups.values() for p in pts]
        lo, hi = min(ys_all), max(ys_all)
        if hi < 4 * lo:
            mid = (lo * hi) ** 0.5
            ax.set_ylim(mid / 2, mid * 2)
    ax.set_xlabel(args.x)
    ax.set_ylabel(y)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return True


if __name__ == "__main__":
    sys.exit(main())
