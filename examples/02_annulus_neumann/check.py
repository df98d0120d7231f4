#!/usr/bin/env python3
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
    out = subprocess.run([vrsph, "study", "--config", os.path.join(d, "study.toml")], check=True,
                         capture_output=True, text=True).stdout
rows = json.loads(out)["rows"]
for r in rows:
    print(f"n={r['n']:3d} N={r['particles']:6d} error_inf={r['error_inf']:.3g} order_inf={r['order_inf']} "
          f"error_l2={r['error_l2']:.3g} mmatrix={r['mmatrix']}")
e = [r["error_inf"] for r in rows]
order = math.log(e[0] / e[-1]) / math.log(4)
assert 0.8 < order < 2.5, f"observed order {order:.2f}: about 1 is expected (first-order flux rows, issue 17)"
assert all(r["mmatrix"] for r in rows)
print(f"example 02: OK (order {order:.2f} from n = 16 to 64)")
