#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The README's figure, docs/img/convergence.png: max error against particles per side on [QW]
Example 5 with perturbed particles (the main job of scripts/run.sh), for traditional SPH, VRSPH
as [QW] publish it and vrsph's default rows, with reference slopes.

usage: readme_figure.py [VRSPH] [OUTPUT]"""
import json
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

VRSPH = sys.argv[1] if len(sys.argv) > 1 else "build/release/apps/vrsph/vrsph"
OUTPUT = sys.argv[2] if len(sys.argv) > 2 else "docs/img/convergence.png"
N = "20,40,80,160"


def rows(*extra):
    p = subprocess.run([VRSPH, "study", "--problem", "qw-ex5", "--cloud", "perturbed", "--n", N, "--seed", "1",
                        "--format", "json", *extra], capture_output=True, text=True, check=True)
    return json.loads(p.stdout)["rows"]


curves = [("traditional SPH", rows("--method", "sph"), "o-"),
          ("VRSPH as in [QW] (profile=qw)", rows("--method", "vrsph", "--method-opt", "vrsph:profile=qw"), "s-"),
          ("vrsph default rows", rows("--method", "vrsph"), "D-")]
fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
for label, rs, style in curves:
    ax.loglog([r["n"] for r in rs], [r["error_inf"] for r in rs], style, label=label)
n = [20, 160]
for order, anchor, text in ((2, curves[1][1][0]["error_inf"], "order 2"), (3, curves[2][1][0]["error_inf"], "order 3")):
    ax.loglog(n, [anchor * 0.5 * (n[0] / m) ** order for m in n], "k:", linewidth=0.8)
    ax.annotate(text, (n[1], anchor * 0.5 * (n[0] / n[1]) ** order), fontsize=8, ha="right", va="top")
ax.set_xticks([20, 40, 80, 160])
ax.set_xticklabels(["20", "40", "80", "160"])
ax.minorticks_off()
ax.set_xlabel("particles per side n (perturbed lattice, h = 3 dx)")
ax.set_ylabel("max error |u - u_h|")
ax.set_title("div((1+x²+y²) grad u) = f on [0,1]², disordered particles")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(OUTPUT)
print(f"wrote {OUTPUT}")
