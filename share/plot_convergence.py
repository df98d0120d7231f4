#!/usr/bin/env python3
"""Plot of a vrsph JSON table (rows[] grouped by a column).

Usage: plot_convergence.py TABLE.json OUT.png --x dx --y error_inf --group method [--title T] [--linear]
Log-log (default): one line per group and reference slopes 1 and 2 (convergence).
--y may list several columns, one panel each, and give each its reference slopes after a
colon, separated by '/': --y seconds_total:1,solver_iterations:0 (cost O(N), flat
iteration count).
--linear: linear axes, no reference slopes (e.g. normalised vibration spectra).
"""
import argparse
import json
import sys

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


def draw_panel(ax, rows, args, y, slopes) -> bool:
    groups = {}
    for r in rows:
        if r.get(args.x) is None or r.get(y) is None or (not args.linear and r[y] <= 0):
            continue
        groups.setdefault(str(r.get(args.group, "")), []).append((r[args.x], r[y]))
    if not groups:
        return False
    markers = "osD^v<>ph*"
    xs_all = []
    for k, (name, pts) in enumerate(sorted(groups.items())):
        pts.sort()
        xs, ys = zip(*pts)
        xs_all += xs
        if args.linear:
            ax.plot(xs, ys, marker=markers[k % len(markers)], markersize=3, label=name)
        else:
            ax.loglog(xs, ys, marker=markers[k % len(markers)], label=name)
    if not args.linear:
        # Reference slopes anchored at the smallest x of the first group.
        x0, x1 = min(xs_all), max(xs_all)
        first = sorted(groups.values())[0]
        y0 = min(v for _, v in first)
        for p, style in zip(slopes, (":", "--", "-.", ":")):
            ax.loglog([x0, x1], [y0, y0 * (x1 / x0) ** p], "k" + style, linewidth=0.8, label=f"slope {p:g}")
        # A nearly flat series (iteration counts) on a log axis: show a factor-of-4 window,
        # or the flat line looks like a slope.
        ys_all = [v for pts in groups.values() for _, v in pts]
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
