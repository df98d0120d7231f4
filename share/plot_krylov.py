#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Residual histories of the Krylov study ([SPE] Figs. 11-12): one panel per discretisation,
one line per preconditioner, relative residual on a log scale against the GMRES iteration.

Usage: plot_krylov.py HISTORY.json OUT.png   (rows: method, preconditioner, iteration, residual)
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {"none": "#7f7f7f", "jacobi": "#ff7f0e", "ilu": "#1f77b4", "amg": "#2ca02c"}


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[1], encoding="utf-8") as f:
        doc = json.load(f)
    series = {}
    for r in doc["rows"]:
        series.setdefault(r["method"], {}).setdefault(r["preconditioner"], []).append((r["iteration"], r["residual"]))
    if not series:
        print("plot_krylov.py: no residual history to plot", file=sys.stderr)
        return 1
    methods = list(series)
    fig, axes = plt.subplots(1, len(methods), figsize=(4.2 * len(methods), 3.8), squeeze=False, sharey=True)
    for ax, m in zip(axes[0], methods):
        for pc, pts in series[m].items():
            pts.sort()
            ax.semilogy([p[0] for p in pts], [max(p[1], 1e-300) for p in pts], label=pc, color=STYLE.get(pc))
        ax.set_title(m)
        ax.set_xlabel("GMRES iteration")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("||r_k|| / ||b||")
    axes[0][-1].legend()
    k = doc.get("krylov", {})
    fig.suptitle(f"{doc.get('problem', '')} {doc.get('dim', '')}D, GMRES({k.get('restart', '?')}), "
                 f"rtol {k.get('rtol', '?')}, contrast {doc.get('contrast', 0):.3g}")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
