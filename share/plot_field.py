#!/usr/bin/env python3
"""Picture of a solution on a point cloud: the field CSV of `vrsph solve` (x,y,z,tag,u[,...,error]).

Usage: plot_field.py FIELDS.csv OUT.png --dim D [--title T]
2D: filled contours of u on the Delaunay triangulation of the particles (and of the error
beside it when the file has an error column). 1D: u (and the error) against x. 3D: the same
as 2D on the particles within half a spacing of the mid-plane z = (zmin + zmax)/2.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402


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
            tri = mtri.Triangulation(x, y)
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
