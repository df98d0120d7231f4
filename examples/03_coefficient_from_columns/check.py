#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs example 03 in a scratch directory and checks what its README states. Usage: check.py VRSPH"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
vrsph = sys.argv[1]
with tempfile.TemporaryDirectory() as d:
    plain = os.path.join(d, "plain.csv")
    subprocess.run([vrsph, "cloud", "--family", "perturbed", "--n", "48", "--seed", "2", "--output", plain],
                   check=True, capture_output=True)
    subprocess.run([sys.executable, os.path.join(here, "add_columns.py"), plain, os.path.join(d, "layered.csv")], check=True)
    shutil.copy(os.path.join(here, "problem.toml"), d)
    row = json.loads(subprocess.run([vrsph, "solve", "--config", os.path.join(d, "problem.toml")], check=True,
                                    capture_output=True, text=True).stdout)["rows"][0]
    with open(os.path.join(d, "u.csv"), encoding="utf-8") as f:
        u = [(float(r["y"]), float(r["u"])) for r in csv.DictReader(f)]
low = max(v for y, v in u if y < 0.4)
high = max(v for y, v in u if y > 0.6)
print(f"N={row['particles']} mmatrix={row['mmatrix']} solver={row['solver']} max u below={low:.4g} above={high:.4g}")
assert row["mmatrix"], "VRSPH keeps the M-matrix with a layered coefficient"
assert min(v for _, v in u) >= -1e-12, "discrete maximum principle: -div(k grad u) = 1 >= 0, u = 0 on the walls, so u >= 0"
assert low > 5 * high, "the soft layer (k = 1) carries most of the solution"
print("example 03: OK")
