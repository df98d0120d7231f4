#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes torus.stl, a closed ASCII STL surface: the torus of radii R = 1 (centre line) and
r = 0.4 (tube) about the z axis, as 96 x 32 quads split into triangles, outward facing.
Usage: make_stl.py DIRECTORY"""
import math
import os
import sys

R, r, nu, nv = 1.0, 0.4, 96, 32


def vertex(i, j):
    # Indices wrap, so the seam's vertices are printed identically (the STL is watertight).
    u, v = 2 * math.pi * (i % nu) / nu, 2 * math.pi * (j % nv) / nv
    return ((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u), r * math.sin(v))


lines = ["solid torus"]
for i in range(nu):
    for j in range(nv):
        a, b, c, d = vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)
        for tri in ((a, b, c), (a, c, d)):  # counter-clockwise seen from outside
            lines += [" facet normal 0 0 0", "  outer loop"]
            lines += ["   vertex %.12g %.12g %.12g" % p for p in tri]
            lines += ["  endloop", " endfacet"]
lines.append("endsolid torus")
with open(os.path.join(sys.argv[1], "torus.stl"), "w") as f:
    f.write("\n".join(lines) + "\n")
