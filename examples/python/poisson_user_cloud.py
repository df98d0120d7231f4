#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""A Poisson problem on a cloud of one's own: the annulus 0.4 <= r <= 1 built with numpy,
Dirichlet on the outer circle, the flux du/dn on the inner one (outward normals point into
the hole), u = x^2 - y^2 + x y (harmonic: f = 0). One call solves it; matplotlib draws it.

    PYTHONPATH=build/release/python python3 examples/python/poisson_user_cloud.py   # writes annulus.png
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import vrsph  # noqa: E402

dx = 0.03
g = np.arange(-1, 1 + dx / 2, dx)
X, Y = np.meshgrid(g, g)
inner = np.column_stack([X.ravel(), Y.ravel()])
r = np.hypot(inner[:, 0], inner[:, 1])
inner = inner[(r > 0.4 + dx / 2) & (r < 1 - dx / 2)]
ring = lambda radius: np.linspace(0, 2 * np.pi, int(round(2 * np.pi * radius / dx)), endpoint=False)  # noqa: E731
t_out, t_in = ring(1.0), ring(0.4)
outer_pts = np.column_stack([np.cos(t_out), np.sin(t_out)])
hole_pts = 0.4 * np.column_stack([np.cos(t_in), np.sin(t_in)])
points = np.vstack([inner, outer_pts, hole_pts])
tags = np.concatenate([np.full(len(inner), vrsph.INTERIOR), np.full(len(outer_pts), vrsph.DIRICHLET),
                       np.full(len(hole_pts), vrsph.NEUMANN)])
normals = np.vstack([np.zeros_like(inner), outer_pts, -hole_pts / 0.4])  # outward from the domain
cloud = vrsph.cloud.from_arrays(points, tags, normals)



def exact(x, y):
    return x**2 - y**2 + x * y


def flux(x, y):  # a du/dn on the hole: grad u = (2x + y, x - 2y), outward normal -(x, y) / 0.4
    return -((2 * x + y) * x + (x - 2 * y) * y) / 0.4


s = vrsph.solve(cloud, f=0.0, g=exact, q=flux, method="vrsph")
x, y = cloud.points.T
err = np.abs(s.u - exact(x, y)).max()
print(f"{len(cloud)} particles, solver {s.solver}, M-matrix {s.mmatrix}, max error {err:.2e}")

fig, ax = plt.subplots(1, 2, figsize=(10, 4.5))
for a, values, title in ((ax[0], s.u, "u"), (ax[1], s.u - exact(x, y), "error")):
    c = a.tricontourf(x, y, values, levels=30)
    a.set_aspect("equal")
    a.set_title(title)
    fig.colorbar(c, ax=a)
fig.savefig("annulus.png", dpi=100)
