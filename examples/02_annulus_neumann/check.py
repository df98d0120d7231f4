#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs example 02 in a scratch directory and checks what its README states. Usage: check.py VRSPH"""
import json
import math
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
    runs = {}
    for profile in ("default", "qw"):
        out = subprocess.run([vrsph, "study", "--config", os.path.join(d, "study.toml"), "--method-opt",
                              f"vrsph:profile={profile}"], check=True, capture_output=True, text=True).stdout
        runs[profile] = json.loads(out)["rows"]
for profile, rows in runs.items():
    for r in rows:
        print(f"{profile:7s} n={r['n']:3d} N={r['particles']:6d} error_inf={r['error_inf']:.3g} order_inf={r['order_inf']} "
              f"error_l2={r['error_l2']:.3g} mmatrix={r['mmatrix']}")
    assert all(r["mmatrix"] for r in rows), profile
# The default (compact rows, balance flux rows): below 1e-7 at every size, and converging.
e = [r["error_inf"] for r in runs["default"]]
assert max(e) < 1e-7 and e[-1] < e[0] / 4, f"default rows: errors {e}"
# [QW]'s rows: the flux rows from VRSPH's own gradient are first order.
q = [r["error_inf"] for r in runs["qw"]]
order = math.log(q[0] / q[-1]) / math.log(4)
assert 0.8 < order < 1.5, f"profile=qw: observed order {order:.2f}, about 1 expected (gradient flux rows)"
print(f"example 02: OK (default {e[0]:.2g} -> {e[-1]:.2g}; profile=qw order {order:.2f} from n = 16 to 64)")
