#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The dam break's surge front z/L against T = t (2g/L)^(1/2): one line per method and
resolution, beside Martin & Moyce's experiments and Koshizuka & Oka's MPS (the JSON's
reference_curves), and in a second panel the column's height at the left wall beside Martin &
Moyce's (height_reference); in Buchner's tank (geometry "buchner ...") the far wall's pressure at probe P1
against T = t (g/H)^(1/2), beside Buchner's record.

Usage: plot_dam_break.py RUN.json OUT.png   (vrsph flow --case dam-break --format json)
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {"martin-moyce a=1.125in": "o", "martin-moyce a=2.25in": "s", "koshizuka-oka mps": "^"}


def draw(axis, runs):
    """One line per run: (T, value) pairs in time order."""
    for name, pts in runs.items():
        pts.sort()
        axis.plot([p[0] for p in pts], [p[1] for p in pts], label=name)


def finish(axis, xlabel, ylabel, title):
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.grid(True, alpha=0.3)
    axis.legend(fontsize=8)


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[1], encoding="utf-8") as f:
        doc = json.load(f)
    buchner = str(doc.get("geometry", "")).startswith("buchner")
    key = "probe_pressure" if buchner else "front_z_over_l"
    runs, heights = {}, {}
    for r in doc["rows"]:
        if r.get("t_star") is None or r.get(key) is None:  # a run that failed before its first sample
            continue
        runs.setdefault(f'{r["method"]} nx={r["nx"]}', []).append((r["t_star"], r[key]))
        if r.get("column_height_over_l") is not None:
            heights.setdefault(f'{r["method"]} nx={r["nx"]}', []).append((r["t_star"], r["column_height_over_l"]))
    if not runs:
        print("plot_dam_break.py: no run to plot (every run failed)", file=sys.stderr)
        return 1
    height_ref = None if buchner else doc.get("height_reference")
    if height_ref:
        fig, (ax, hax) = plt.subplots(1, 2, figsize=(11.0, 4.4))
    else:
        fig, ax = plt.subplots(figsize=(6.0, 4.4))
    draw(ax, runs)
    for c in doc.get("reference_curves", []):
        ax.plot(c["t_star"], c["probe_pressure" if buchner else "z_over_l"], MARKERS.get(c["name"], "x"), mfc="none",
                color="k", label=c["name"])
    ax.set_xlim(0, max(max(p[0] for p in pts) for pts in runs.values()) * 1.05)
    if buchner:
        finish(ax, "T = t (g/H)^(1/2)", "p / (rho g H) at probe P1", "dam break, Buchner's tank: far-wall pressure")
    else:
        ax.set_ylim(1, 4.2)
        finish(ax, "T = t (2g/L)^(1/2)", "z / L", "dam break: surge front")
    if height_ref:
        draw(hax, heights)
        hax.plot(height_ref["t_star"], height_ref["height_over_l"], "d", mfc="none", color="k", label=height_ref["name"])
        hax.set_xlim(ax.get_xlim())
        hax.set_ylim(0, 2.1)
        finish(hax, "T = t (2g/L)^(1/2)", "column height at the left wall / L", "dam break: residual column")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
