#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""L-shaped domain [-1,1]^2 minus (0,1]x[-1,0): perturbed lattice clouds l_{n}.csv for the
sizes given (spacing 2/n), boundary particles tagged dirichlet. Standard library only.

Usage: make_clouds.py OUTDIR N [N ...]
"""
import os
import random
import sys


def inside(x, y):
    return -1 <= x <= 1 and -1 <= y <= 1 and not (x > 0 and y < 0)


def main() -> int:
    out, sizes = sys.argv[1], [int(v) for v in sys.argv[2:]]
    for n in sizes:
        h = 2 / n
        rng = random.Random(n)
        rows = []
        for i in range(n + 1):
            for j in range(n + 1):
                x, y = -1 + i * h, -1 + j * h
                if not inside(x, y):
                    continue
                # On the boundary: an outer face, or the two edges of the removed quadrant.
                boundary = i in (0, n) or j in (0, n) or (x >= 0 and abs(y) < 1e-12) or (y <= 0 and abs(x) < 1e-12)
                if not boundary:
                    x += rng.uniform(-0.3, 0.3) * h
                    y += rng.uniform(-0.3, 0.3) * h
                rows.append(f"{x!r},{y!r},{'dirichlet' if boundary else 'interior'}")
        with open(os.path.join(out, f"l_{n}.csv"), "w", encoding="utf-8") as f:
            f.write("x,y,tag\n" + "\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
