#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs example 01 in a scratch directory and checks what its README states. Usage: check.py VRSPH"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
vrsph = sys.argv[1]
with tempfile.TemporaryDirectory() as d:
    subprocess.run([sys.executable, os.path.join(here, "make_clouds.py"), d, "16", "32", "64"], check=True)
    shutil.copy(os.path.join(here, "study.toml"), d)
    out = subprocess.run([vrsph, "study", "--config", os.path.join(d, "study.toml")], check=True,
                         capture_output=True, text=True).stdout
rows = {(r["method"], r["n"]): r for r in json.loads(out)["rows"]}
for (m, n), r in sorted(rows.items()):
    print(f"{m:6s} n={n:3d} N={r['particles']:5d} error_inf={r['error_inf']:.3g} interior={r['error_inf_interior']:.3g} "
          f"order_inf={r['order_inf']} mmatrix={r['mmatrix']}")
v16, v64, f64 = rows[("vrsph", 16)], rows[("vrsph", 64)], rows[("fpm", 64)]
assert v64["error_inf"] < v16["error_inf"] / 2.5, "VRSPH must converge on the L-shape (about order 1 in max norm)"
assert all(r["mmatrix"] for (m, _), r in rows.items() if m == "vrsph"), "VRSPH keeps the M-matrix"
assert v64["error_inf"] < f64["error_inf"], "VRSPH beats FPM at n = 64 on this singular problem"
print("example 01: OK")
