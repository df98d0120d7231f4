# SPDX-License-Identifier: BSD-3-Clause
"""The cavity's centre-line profiles (`vrsph flow --case cavity --profile-output lines.csv`) beside
Ghia et al.'s points and the converged P2-P1 solution, as a PNG:

    /usr/bin/python3 scripts/cavity_profiles_plot.py lines.csv cavity.png [--title "Re = 100"]
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv")
    parser.add_argument("png")
    parser.add_argument("--title", default="lid-driven cavity")
    a = parser.parse_args()
    series = defaultdict(lambda: defaultdict(list))
    with open(a.csv) as f:
        for row in csv.DictReader(f):
            series[row["series"]][row["line"]].append((float(row["s"]), float(row["value"])))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8))
    for name, lines in series.items():
        reference = name == "ghia" or name.startswith("p2-p1")
        style = dict(linestyle="", marker="o" if name == "ghia" else "x", markersize=5) if reference else dict(lw=1.3)
        if "u(0.5;y)" in lines:
            s, v = zip(*sorted(lines["u(0.5;y)"]))
            left.plot(v, s, label=name, **style)
        if "v(x;0.5)" in lines:
            s, v = zip(*sorted(lines["v(x;0.5)"]))
            right.plot(s, v, label=name, **style)
    left.set_xlabel("u(0.5, y)")
    left.set_ylabel("y")
    right.set_xlabel("x")
    right.set_ylabel("v(x, 0.5)")
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)


if __name__ == "__main__":
    main()
