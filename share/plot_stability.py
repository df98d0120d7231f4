#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Complex-plane cloud of von Neumann growth factors with the unit circle ([SPE] Fig. 5).

Usage: plot_stability.py DATA.json OUT.png
DATA: {"title": ..., "methods": {name: [[re, im, boundary(0|1)], ...]}} as `vrsph stability --plot` writes it.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main() -> int:
    with open(sys.argv[1], encoding="utf-8") as f:
        data = json.load(f)
    methods = data["methods"]
    fig, axes = plt.subplots(1, len(methods), figsize=(4.2 * len(methods), 4.2), squeeze=False)
    t = np.linspace(0, 2 * np.pi, 400)
    for ax, (name, pts) in zip(axes[0], methods.items()):
        a = np.asarray(pts, dtype=float).reshape(-1, 3)
        inner, outer = a[a[:, 2] == 0], a[a[:, 2] == 1]
        ax.plot(np.cos(t), np.sin(t), "k-", lw=0.8, label="|λ| = 1")
        ax.scatter(outer[:, 0], outer[:, 1], s=2, c="tab:orange", label="near the boundary")
        ax.scatter(inner[:, 0], inner[:, 1], s=2, c="tab:blue", label="interior")
        ax.set_aspect("equal")
        ax.set_title(name)
        ax.set_xlabel("Re λ")
        ax.set_ylabel("Im λ")
        ax.legend(loc="lower left", fontsize=7, markerscale=4)
    fig.suptitle(data.get("title", ""))
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
