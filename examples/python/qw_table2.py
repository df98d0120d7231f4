#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""[QW] Table 2 (Example 5 on perturbed particles, mean over five seeds) in ten lines."""
import vrsph

rows = vrsph.study(problem="qw-ex5", methods=["vrsph", "sph"], cloud="perturbed", n=[20, 40, 80, 160],
                   seeds=[1, 2, 3, 4, 5])
print(f"{'method':7s}{'n':>5s}{'error_inf':>12s}{'order':>7s}  M-matrix")
for r in rows:
    order = "" if r["order_inf"] is None else f"{r['order_inf']:.2f}"
    print(f"{r['method']:7s}{r['n']:5d}{r['error_inf']:12.3e}{order:>7s}  {r['mmatrix']}")
