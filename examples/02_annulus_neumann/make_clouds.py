#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Annulus 0.5 <= r <= 1: particles on rings (spacing ~ 0.5/n radially and along each ring,
every ring rotated by a random angle), the outer ring Dirichlet, the inner ring Neumann with
the domain's outward normal -x/r. Writes a_{n}.csv for the sizes given. Standard library only.

Usage: make_clouds.py OUTDIR N [N ...]
"""
import math
import os
import random
import sys


def main() -> int:
    out, sizes = sys.argv[1], [int(v) for v in sys.argv[2:]]
    for n in sizes:
        rng = random.Random(7 * n)
        dr = 0.5 / n
        rows = []
        for k in range(n + 1):
            r = 0.5 + k * dr
            m = max(8, round(2 * math.pi * r / dr))
            shift = rng.uniform(0, 2 * math.pi / m)
            for j in range(m):
                t = shift + 2 * math.pi * j / m
                x, y = r * math.cos(t), r * math.sin(t)
                if k == 0:
                    rows.append(f"{x!r},{y!r},neumann,{-x / r!r},{-y / r!r}")
                elif k == n:
                    rows.append(f"{x!r},{y!r},dirichlet,{x / r!r},{y / r!r}")
                else:
                    rows.append(f"{x!r},{y!r},interior,0,0")
        with open(os.path.join(out, f"a_{n}.csv"), "w", encoding="utf-8") as f:
            f.write("x,y,tag,nx,ny\n" + "\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
