#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Accuracy per unknown against P1 finite elements on exactly the same points (issue 17 item 3).

For each cloud family and n: `vrsph cloud --family F --n N --output cloud.csv` writes the points,
the FEniCSx P1 + BoomerAMG peer (../shared/anchors/fenicsx_ex5.py --points cloud.csv, as provided)
solves [QW] Example 5 on their Delaunay triangulation, and `vrsph study` solves it with each VRSPH
variant on the same cloud. Prints a Markdown table (and writes --csv): max-norm error, observed
order, nonzeros per row, M-matrix, seconds (each side's own total, measured in the same run).

Run: python3 scripts/p1_same_points.py [--vrsph build/release/apps/vrsph/vrsph] [--n 80,160,320,640]
     [--families uniform,perturbed,centroids] [--csv out.csv]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

VARIANTS = [
    ("vrsph", []),
    ("vrsph prefer=near", ["--method-opt", "vrsph:prefer=near"]),
    ("vrsph rhs=compact", ["--method-opt", "vrsph:rhs=compact"]),
]


def vrsph_study(exe, family, n, extra):
    out = subprocess.run([exe, "study", "--method", "vrsph", "--cloud", family, "--n", str(n), "--format", "json"] + extra,
                         check=True, capture_output=True, text=True).stdout
    row = json.loads(out)["rows"][0]
    return {"error_inf": row["error_inf"], "nnz_per_row": row["nnz_per_row"], "mmatrix": row["mmatrix"],
            "seconds": row["seconds_total"], "nodes": row["N"]}


def anchor(script, points):
    out = subprocess.run(["/usr/bin/python3", script, "--points", points], check=True, capture_output=True, text=True).stdout
    line = [l for l in out.splitlines() if l.startswith("{")][-1]
    r = json.loads(line)
    return {"error_inf": r["error_inf"], "nnz_per_row": float("nan"), "mmatrix": "", "seconds": r["total"],
            "nodes": r["nodes"]}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vrsph", default=os.path.join(here, "..", "build", "release", "apps", "vrsph", "vrsph"))
    ap.add_argument("--anchor", default=os.path.join(here, "..", "..", "shared", "anchors", "fenicsx_ex5.py"))
    ap.add_argument("--n", default="80,160,320,640")
    ap.add_argument("--families", default="uniform,perturbed,centroids")
    ap.add_argument("--max-particles", type=int, default=1_500_000, help="skip clouds larger than this")
    ap.add_argument("--csv")
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for family in a.families.split(","):
            prev = {}
            for n in [int(v) for v in a.n.split(",")]:
                points = os.path.join(tmp, f"{family}_{n}.csv")
                subprocess.run([a.vrsph, "cloud", "--family", family, "--n", str(n), "--output", points], check=True,
                               capture_output=True)
                with open(points) as fh:
                    size = sum(1 for _ in fh) - 1
                if size > a.max_particles:
                    print(f"skip {family} n={n}: {size} particles", file=sys.stderr)
                    continue
                results = [("P1 (FEniCSx)", anchor(a.anchor, points))]
                for name, extra in VARIANTS:
                    results.append((name, vrsph_study(a.vrsph, family, n, extra)))
                for name, r in results:
                    order = math.log2(prev[name] / r["error_inf"]) if name in prev else float("nan")
                    prev[name] = r["error_inf"]
                    rows.append({"cloud": family, "n": n, "nodes": r["nodes"], "scheme": name, **r, "order": order})
                    print(f"{family} n={n} {name}: {r['error_inf']:.3e} ({r['seconds']:.2f} s)", file=sys.stderr)
    cols = ["cloud", "n", "nodes", "scheme", "error_inf", "order", "nnz_per_row", "mmatrix", "seconds"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        cells = []
        for c in cols:
            v = r[c]
            cells.append(f"{v:.3e}" if c == "error_inf" else f"{v:.2f}" if isinstance(v, float) and not math.isnan(v)
                         else "–" if isinstance(v, float) else str(v))
        print("| " + " | ".join(cells) + " |")
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
