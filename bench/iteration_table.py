#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Solver iterations of the default PETSc solver (GMRES + BoomerAMG) across sizes and problems.

Usage: iteration_table.py VRSPH_BINARY [--sizes 100,316,1000] [--threads 2] [--json out.json]

Runs `vrsph study --solver petsc` (VRSPH on perturbed clouds unless a problem says otherwise)
for each problem below and size n (N ~ (n+1)^d), and prints one Markdown row per problem:
iterations at every size, the ratio largest/smallest, and the max-norm error at the largest
size (which must keep falling as O(h^2): a flat iteration count bought with a wrong solution
would be worthless). The problems are the ones issue 13 names: Example 5 in 2D and 3D, the
disk, an inhomogeneous problem of the held-out kind, a coefficient contrast of 10^4, and
mixed and pure Neumann boundary conditions.
"""
import argparse
import json
import os
import subprocess
import sys

PROBLEMS = [
    ("Example 5, 2D", ["--problem", "qw-ex5", "--dim", "2"]),
    ("disk, 2D", ["--problem", "qw-ex5", "--dim", "2", "--cloud", "disk"]),
    ("inhomogeneous: u = e^x sin 2y + xy, a = 1 + sin(3x)cos(2y)/2",
     ["--problem", "custom", "--dim", "2", "--u", "exp(x)*sin(2*y)+x*y", "--a", "1+0.5*sin(3*x)*cos(2*y)"]),
    ("contrast 10^4: a = 10^(4x), u = sin-pi",
     ["--problem", "custom", "--dim", "2", "--u", "sin-pi", "--a", "10^(4*x)"]),
    ("mixed: Neumann on x0, x1", ["--problem", "qw-ex5", "--dim", "2", "--neumann", "x0,x1"]),
    ("pure Neumann (constant fixed), u = cos-pi",
     ["--problem", "custom", "--dim", "2", "--u", "cos-pi", "--neumann", "all", "--fix-constant"]),
]
PROBLEMS_3D = [("Example 5, 3D", ["--problem", "qw-ex5", "--dim", "3"])]


def run(binary, args, sizes, threads):
    cmd = [binary, "study", "--method", "vrsph", "--solver", "petsc", "--format", "json", "--n", ",".join(str(n) for n in sizes)]
    if "--cloud" not in args:
        cmd += ["--cloud", "perturbed"]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    out = subprocess.run(cmd + args, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out)["rows"]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("--sizes", default="100,316,1000")
    ap.add_argument("--sizes-3d", default="22,46,100")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json")
    a = ap.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    sizes3 = [int(s) for s in a.sizes_3d.split(",")]
    results = []
    for name, args in PROBLEMS + PROBLEMS_3D:
        rows = run(a.binary, args, sizes3 if name in dict(PROBLEMS_3D) else sizes, a.threads)
        results.append({"problem": name, "N": [r["N"] for r in rows], "iterations": [r["solver_iterations"] for r in rows],
                        "error_inf": [r["error_inf"] for r in rows], "order_inf": [r["order_inf"] for r in rows],
                        "reason": rows[-1]["solver_reason"]})
        print(f"done: {name}", file=sys.stderr)
    print("| problem | N | iterations | largest/smallest | error_inf at largest N | observed order |")
    print("|---|---|---|---|---|---|")
    for r in results:
        its = r["iterations"]
        print(f"| {r['problem']} | {' / '.join(f'{n:.2g}' for n in r['N'])} | {' / '.join(map(str, its))} | "
              f"{its[-1] / max(its[0], 1):.2f} | {r['error_inf'][-1]:.3g} | {r['order_inf'][-1]:.2f} |")
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump(results, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
