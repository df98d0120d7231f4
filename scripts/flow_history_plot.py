# SPDX-License-Identifier: BSD-3-Clause
"""Columns of `vrsph flow --history FILE.csv` against time, one panel per column and one curve per
run (method, nx; a second file's runs drawn dashed, e.g. with and without shifting), as a PNG:

    /usr/bin/python3 scripts/flow_history_plot.py history.csv out.png \\
        [--columns error_u_mean,min_support_isotropy] [--dashed other.csv] [--label solid,dashed] [--title T]

Columns that hold errors or speeds are drawn on a log scale.
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LOG_COLUMNS = {"error_u_mean", "error_u_inf", "error_p_mean", "decay_rate_error", "max_div_u", "steady_residual",
               "max_speed", "kinetic_energy"}


def read_runs(path, columns):
    runs = defaultdict(lambda: defaultdict(list))
    with open(path, encoding="utf-8") as f:
        reader = csv.DictReader(f)
        missing = [c for c in columns + ["t", "method", "nx"] if c not in (reader.fieldnames or [])]
        if missing:
            raise SystemExit(f"{path}: no column {', '.join(missing)} (is it a --history file?)")
        for row in reader:
            key = f"{row['method']} nx={row['nx']}"
            runs[key]["t"].append(float(row["t"]))
            for c in columns:
                runs[key][c].append(float(row[c]) if row[c] not in ("", "nan") else float("nan"))
    return runs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv")
    parser.add_argument("png")
    parser.add_argument("--columns", default="error_u_mean,min_support_isotropy")
    parser.add_argument("--dashed", help="a second history whose runs are drawn dashed")
    parser.add_argument("--label", default="", help="names of the two files' runs, comma-separated")
    parser.add_argument("--title", default="")
    a = parser.parse_args()
    columns = [c for c in a.columns.split(",") if c]
    labels = (a.label.split(",") + ["", ""])[:2]
    files = [(a.csv, "-", labels[0])] + ([(a.dashed, "--", labels[1])] if a.dashed else [])
    fig, axes = plt.subplots(1, len(columns), figsize=(5.2 * len(columns), 4.2), squeeze=False)
    colours = {}
    for path, style, label in files:
        for key, series in read_runs(path, columns).items():
            colour = colours.setdefault(key, f"C{len(colours)}")
            for ax, c in zip(axes[0], columns):
                ax.plot(series["t"], series[c], style, color=colour, lw=1.3, label=f"{key} {label}".strip())
    for ax, c in zip(axes[0], columns):
        ax.set_xlabel("t")
        ax.set_ylabel(c)
        if c in LOG_COLUMNS:
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
