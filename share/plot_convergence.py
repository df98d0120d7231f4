#!/usr/bin/env python3
"""Plot of a vrsph JSON table (rows[] grouped by a column).

Usage: plot_convergence.py TABLE.json OUT.png --x dx --y error_inf --group method [--title T] [--linear]
Log-log (default): one line per group and reference slopes 1 and 2 (convergence).
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
    groups = {}
    for r in rows:
        if r.get(args.x) is None or r.get(args.y) is None or (not args.linear and r[args.y] <= 0):
            continue
        groups.setdefault(str(r.get(args.group, "")), []).append((r[args.x], r[args.y]))
    if not groups:
        print("plot_convergence.py: nothing to plot", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(figsize=(6, 4.5))
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
        y0 = min(y for _, y in first)
        for p, style in ((1, ":"), (2, "--")):
            ax.loglog([x0, x1], [y0, y0 * (x1 / x0) ** p], "k" + style, linewidth=0.8, label=f"order {p}")
    ax.set_xlabel(args.x)
    ax.set_ylabel(args.y)
    ax.set_title(args.title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
