#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Picture of a solution on a point cloud: the field CSV of `vrsph solve` (x,y,z,tag,u[,...,error]).

Usage: plot_field.py FIELDS.csv OUT.png --dim D [--title T]
2D: filled contours of u on the Delaunay triangulation of the particles (and of the error
beside it when the file has an error column), without the triangles that bridge a hole or a
re-entrant corner: those whose longest edge exceeds a few local spacings. 1D: u (and the error) against x. 3D: the same
as 2D on the particles within half a spacing of the mid-plane z = (zmin + zmax)/2.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402


def inside_only(tri, factor=3.0, boundary=None):
    """Masks the Delaunay triangles that leave the cloud. A particle's local spacing is the mean
    of its two shortest Delaunay edges (every particle has two short ones, a convex corner of the
    domain too, whose other edges may span a hole); a triangle is kept when its longest edge is at most
    `factor` times the largest local spacing of its corners. The convex hull's triangles over a
    hole or a re-entrant corner have edges of the hole's size and are dropped. `boundary`: per
    particle its outward normal (nx, ny) or None; a triangle with only boundary corners is
    dropped too when its centroid lies outside (beyond the tangent) at two of them: the small
    triangles that cut a re-entrant corner or a hole's rim at a coarse resolution."""
    x, y = tri.x, tri.y
    incident = [[] for _ in range(len(x))]
    for a, b in tri.edges:
        length = ((x[a] - x[b]) ** 2 + (y[a] - y[b]) ** 2) ** 0.5
        incident[a].append(length)
        incident[b].append(length)
    spacing = []
    for lengths in incident:
        lengths.sort()
        short = lengths[:2] or [0.0]
        spacing.append(sum(short) / len(short))
    mask = []
    for t in tri.triangles:
        longest = max(((x[t[i]] - x[t[j]]) ** 2 + (y[t[i]] - y[t[j]]) ** 2) ** 0.5 for i, j in ((0, 1), (1, 2), (2, 0)))
        drop = longest > factor * max(spacing[k] for k in t)
        if not drop and boundary is not None and all(boundary[k] is not None for k in t):
            cx, cy = sum(x[k] for k in t) / 3, sum(y[k] for k in t) / 3
            outside = sum((cx - x[k]) * boundary[k][0] + (cy - y[k]) * boundary[k][1] > 0 for k in t)
            drop = outside >= 2
        mask.append(drop)
    tri.set_mask(mask)
    return tri


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("fields")
    ap.add_argument("png")
    ap.add_argument("--dim", type=int, required=True)
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.fields, encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print("plot_field.py: no particles", file=sys.stderr)
        return 1
    x = [float(r["x"]) for r in rows]
    y = [float(r["y"]) for r in rows]
    z = [float(r["z"]) for r in rows]
    names = ["u"] + (["error"] if "error" in rows[0] else [])
    # Outward normals of the boundary particles, when the file has them (vrsph writes them
    # for clouds with normals): None for interior particles and zero normals.
    normals = None
    if "nx" in rows[0]:
        normals = []
        for r in rows:
            n = (float(r["nx"]), float(r["ny"]))
            normals.append(n if r["tag"] in ("dirichlet", "neumann") and n != (0.0, 0.0) else None)
    values = {n: [float(r[n]) for r in rows] for n in names}
    where = ""
    if a.dim == 3:
        zmin, zmax = min(z), max(z)
        mid = 0.5 * (zmin + zmax)
        half = 0.5 * (zmax - zmin) / max(round(len(z) ** (1 / 3)) - 1, 1)
        keep = [i for i in range(len(z)) if abs(z[i] - mid) <= half + 1e-12]
        x, y = [x[i] for i in keep], [y[i] for i in keep]
        values = {n: [v[i] for i in keep] for n, v in values.items()}
        where = f" (slice z = {mid:.3g} ± {half:.2g})"
    fig, axes = plt.subplots(1, len(names), figsize=(5.5 * len(names), 4.5), squeeze=False)
    for ax, n in zip(axes[0], names):
        if a.dim == 1:
            order = sorted(range(len(x)), key=lambda i: x[i])
            ax.plot([x[i] for i in order], [values[n][i] for i in order], marker=".", markersize=3)
            ax.set_xlabel("x")
            ax.set_ylabel(n)
        else:
            tri = inside_only(mtri.Triangulation(x, y), boundary=normals if a.dim == 2 else None)
            c = ax.tricontourf(tri, values[n], levels=24, cmap="viridis" if n == "u" else "coolwarm")
            fig.colorbar(c, ax=ax)
            ax.set_aspect("equal")
            ax.set_xlabel("x")
            ax.set_ylabel("y")
        ax.set_title(n + where)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
