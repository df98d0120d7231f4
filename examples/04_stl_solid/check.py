#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs example 04 in a scratch directory and checks what its README states. Usage: check.py VRSPH"""
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
    subprocess.run([sys.executable, os.path.join(here, "make_stl.py"), d], check=True)
    for n in (6, 12, 24):
        report = subprocess.run([vrsph, "cloud", "--geometry", os.path.join(d, "torus.stl"), "--spacing", str(1 / n),
                                 "--family", "perturbed", "--output", os.path.join(d, f"torus_{n}.csv"),
                                 "--format", "json"], check=True, capture_output=True, text=True).stdout
        c = json.loads(report)
        print(f"cloud n={n}: {c['particles']} particles, {c['dirichlet']} on the surface, covering radius "
              f"{c['covering_radius_over_spacing']:.2f} spacings (+ up to {c['covering_radius_uncertainty'] * n:.2f})")
        assert c["neumann"] == 0 and c["dirichlet"] > 0 and c["isolated_particles"] == 0
        assert c["covering_radius_over_spacing"] < 1.5, "the fill must leave no hole wider than ~1.5 spacings"
    shutil.copy(os.path.join(here, "study.toml"), d)
    out = subprocess.run([vrsph, "study", "--config", os.path.join(d, "study.toml")], check=True,
                         capture_output=True, text=True).stdout
rows = json.loads(out)["rows"]
for r in rows:
    print(f"{r['method']:6s} n={r['n']:3d} N={r['particles']:6d} error_inf={r['error_inf']:.3g} "
          f"order_inf={r['order_inf']} mmatrix={r['mmatrix']}")
err = {m: [r["error_inf"] for r in rows if r["method"] == m] for m in ("vrsph", "sph")}
order = math.log(err["vrsph"][0] / err["vrsph"][-1]) / math.log(4)
assert 2.5 < order < 5.5, f"VRSPH observed order {order:.2f}: about 3 or more is expected (compact rows)"
assert all(r["mmatrix"] for r in rows if r["method"] == "vrsph")
assert err["vrsph"][-1] < err["sph"][-1] / 100, "VRSPH must beat SPH by orders of magnitude"
print(f"example 04: OK (VRSPH order {order:.2f} from n = 6 to 24)")
