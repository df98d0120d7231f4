#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Issue 30's before/after table: the max-norm error and observed orders of `vrsph` with its
default rows (rhs=compact, flux=balance) against [QW]'s rows (profile=qw, the defaults before
issue 30) on the problems a new user meets: a perforated plate with Neumann holes, [QW]
Example 5 on perturbed and triangle-centroid clouds, the annulus of example 02 (Neumann inner
circle) and the 3D ball. Every number comes from `vrsph study --format json` in this run.

Usage: python3 scripts/defaults_table.py [VRSPH] > table.md"""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
VRSPH = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "build", "release", "apps", "vrsph", "vrsph")
PROFILES = (("qw", ["--method-opt", "vrsph:profile=qw"]), ("default", []))


def plate(d):
    """The unit square minus two discs of radius 0.12 (GeoJSON, holes clockwise)."""
    def circle(cx, cy, r, n=96):
        pts = [[cx + r * math.cos(-2 * math.pi * k / n), cy + r * math.sin(-2 * math.pi * k / n)] for k in range(n)]
        return pts + [pts[0]]
    path = os.path.join(d, "plate.geojson")
    with open(path, "w") as f:
        json.dump({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]],
                                                     circle(0.3, 0.5, 0.12), circle(0.7, 0.5, 0.12)]}, f)
    return path


def study(args, cwd):
    p = subprocess.run([VRSPH, "study", *args, "--format", "json"], capture_output=True, text=True, cwd=cwd)
    if p.returncode != 0:
        raise SystemExit(f"vrsph study {' '.join(args)}: {p.stderr}")
    return json.loads(p.stdout)["rows"]


def main():
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([sys.executable, os.path.join(HERE, "..", "examples", "02_annulus_neumann", "make_clouds.py"), d,
                        "16", "32", "64"], check=True, capture_output=True)
        holes = "((x-0.3)^2+(y-0.5)^2<0.0169) || ((x-0.7)^2+(y-0.5)^2<0.0169)"
        cases = [
            ("plate, Neumann holes, perturbed fill", ["--geometry", plate(d), "--spacing", "0.05,0.025,0.0125,0.00625",
                                                      "--fill", "perturbed", "--neumann-where", holes,
                                                      "--u", "exp(x)*sin(pi*y)+x^2"]),
            ("Example 5, perturbed", ["--problem", "qw-ex5", "--cloud", "perturbed", "--n", "20,40,80,160"]),
            ("Example 5, centroids", ["--problem", "qw-ex5", "--cloud", "centroids", "--n", "10,20,40,80"]),
            ("annulus, Neumann inner circle (example 02)", ["--cloud-file-pattern", os.path.join(d, "a_{n}.csv"),
                                                            "--n", "16,32,64", "--u", "exp(x)*sin(y) + x*y",
                                                            "--a", "1 + x^2 + y^2"]),
            ("3D ball (Dirichlet sphere)", ["--dim", "3", "--cloud", "disk", "--n", "8,12,16", "--u",
                                            "sin(pi*x)*sin(pi*y)*sin(pi*z)", "--a", "1+x^2+y^2+z^2"]),
        ]
        print("| problem | rows | particles | error_inf | orders | fitted | M-matrix | infeasible |")
        print("|---|---|---|---|---|---|---|---|")
        for name, args in cases:
            for profile, extra in PROFILES:
                rows = study(args + ["--method", "vrsph"] + extra, d)
                sizes = [r.get("N", r.get("particles")) for r in rows]
                errors = [r["error_inf"] for r in rows]
                orders = [r["order_inf"] for r in rows[1:]]
                h = [r.get("spacing") or r["h"] for r in rows]
                n = len(errors)
                lx = [math.log(v) for v in h]
                ly = [math.log(v) for v in errors]
                mx, my = sum(lx) / n, sum(ly) / n
                fit = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
                print(f"| {name} | {profile} | {', '.join(str(s) for s in sizes)} | "
                      f"{', '.join(f'{e:.3g}' for e in errors)} | {', '.join(f'{o:.2f}' for o in orders)} | {fit:.2f} | "
                      f"{'yes' if all(r['mmatrix'] for r in rows) else 'no'} | "
                      f"{', '.join(str(r['infeasible']) for r in rows)} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
