#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The Laplacian of u = sin(pi x) sin(pi y) on a cloud made with numpy (a lattice jittered by
up to half a spacing, boundary particles on the square's edges): VRSPH against classic SPH.

    PYTHONPATH=build/release/python python3 examples/python/laplacian_random_cloud.py
"""
import numpy as np

import vrsph

rng = np.random.default_rng(7)
n = 40
dx = 1.0 / n
g = np.linspace(0, 1, n + 1)
X, Y = np.meshgrid(g, g, indexing="ij")
pts = np.column_stack([X.ravel(), Y.ravel()])
boundary = (pts == 0).any(axis=1) | (pts == 1).any(axis=1)
pts[~boundary] += rng.uniform(-0.5 * dx, 0.5 * dx, size=(int((~boundary).sum()), 2))
cloud = vrsph.cloud.from_arrays(pts, np.where(boundary, vrsph.DIRICHLET, vrsph.INTERIOR))

x, y = cloud.points.T
u = np.sin(np.pi * x) * np.sin(np.pi * y)
exact = -2 * np.pi**2 * u
# Rows one support radius (3 dx) away from the walls: SPH's kernel is truncated at the wall.
inner = (cloud.tags == vrsph.INTERIOR) & (np.minimum.reduce([x, y, 1 - x, 1 - y]) > 3 * dx)
for method in ("vrsph", "sph"):
    L = vrsph.stencil(cloud, method=method, operator="laplacian", h_factor=3)  # scipy.sparse CSR
    err = np.abs(L @ u - exact)[inner].max() / np.abs(exact).max()
    print(f"{method.upper():6s} relative max error of the Laplacian: {err:.2e}  ({L.nnz / len(cloud):.1f} nonzeros per row)")
