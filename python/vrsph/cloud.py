# SPDX-License-Identifier: BSD-3-Clause
"""Point clouds: the built-in families of the papers' studies, clouds from arrays and
geometries (the same generators as ``vrsph cloud``)."""
from __future__ import annotations

import numpy as np

from . import _vrsph
from ._vrsph import Cloud

__all__ = ["Cloud", "lattice", "perturbed", "centroids", "disk", "from_arrays", "from_geometry", "with_periodic_box"]


def lattice(dim: int = 2, n: int = 20, domain: str = "unit", layout: str = "vertex", periodic: str = "",
            distributed: bool = False) -> Cloud:
    """The uniform lattice of n intervals per direction on [0,1]^d (``domain="unit"``) or
    [-1,1]^d (``"symmetric"``); layout "vertex" ([QW] layout A, boundary particles on the
    faces) or "cells" (layout B). ``periodic="x,y"`` (or ``"all"``): the box wraps around
    along those axes (n particles per period, no boundary particles there); every operator
    and solve then sees across the faces. ``distributed=True`` (under mpirun): this rank's part,
    as for :func:`perturbed`."""
    return _vrsph._generated("uniform", dim, n, domain, layout, 0.5, 1, False, 0.0, periodic, bool(distributed))


def perturbed(dim: int = 2, n: int = 20, delta: float = 0.5, seed: int = 1, domain: str = "unit",
              layout: str = "vertex", perturb_boundary: bool = False, regular_layer: float = 0.0,
              periodic: str = "", distributed: bool = False) -> Cloud:
    """The lattice with interior particles moved by U(-delta dx, delta dx) per coordinate
    ([QW]'s perturbed clouds; the same seed gives the CLI's cloud); ``periodic`` as for
    :func:`lattice` (moves across a periodic face wrap). ``distributed=True`` (under mpirun):
    this rank's part of the cloud, the parts in rank order being the whole cloud, for
    ``solve(..., distributed=True)``."""
    return _vrsph._generated("perturbed", dim, n, domain, layout, delta, seed, perturb_boundary, regular_layer,
                             periodic, bool(distributed))


def centroids(dim: int = 2, n: int = 20, seed: int = 1, domain: str = "unit") -> Cloud:
    """Centroids of a Delaunay mesh of a jittered lattice ([QW] §5's third family)."""
    return _vrsph._generated("centroids", dim, n, domain, "vertex", 0.5, seed, False, 0.0)


def disk(dim: int = 2, n: int = 20) -> Cloud:
    """Particles in the disk (ball) inscribed in the unit box, boundary particles with radial normals."""
    return _vrsph._generated("disk", dim, n, "unit", "vertex", 0.5, 1, False, 0.0)


def from_arrays(points, tags, normals=None, periodic: str = "", box=None) -> Cloud:
    """A cloud from an (N, d) float array of positions, N integer tags (0 interior, 1 Dirichlet,
    2 Neumann, 3 ghost) and, for Neumann particles, (N, d) outward unit normals.

    ``periodic="x,y"`` (or ``"all"``) with ``box=(lo, hi)`` (two length-d sequences, or the
    2d numbers lo then hi): the box [lo, hi) wraps around along those axes, as for the
    generators; every particle must lie in [lo, hi) along them (wrap them first:
    ``lo + (x - lo) % (hi - lo)``), else InputError. The box is never guessed from the
    particles (their last layer sits a spacing short of the far face).

    Integer ``points`` are refused (convert them deliberately); non-contiguous arrays are
    copied; NaN, duplicate-free checks and the rest are the library's."""
    return with_periodic_box(_vrsph._from_arrays(points, np.asarray(tags), normals), periodic, box)


def with_periodic_box(cloud: Cloud, periodic: str, box=None) -> Cloud:
    """A copy of ``cloud`` in the box ``box=(lo, hi)`` periodic along ``periodic`` (see
    :func:`from_arrays`); ``periodic=""`` and no box: the cloud itself."""
    if not periodic:
        if box is not None:
            raise _vrsph.ConfigError("box= needs periodic= (it is the box whose faces wrap)")
        return cloud
    if box is None:
        raise _vrsph.ConfigError("periodic= needs box=(lo, hi): the periodic box is not guessed from the particles")
    try:
        corners = np.asarray(box, dtype=float).reshape(2, cloud.dim)
    except (TypeError, ValueError) as e:
        raise _vrsph.ConfigError(f"box: expected (lo, hi) with {cloud.dim} coordinates each for a {cloud.dim}D cloud, "
                                 f"got {box!r}") from e
    return _vrsph._with_periodic_box(cloud, list(corners[0]), list(corners[1]), str(periodic))


def from_geometry(path: str, spacing: float, fill: str = "uniform", delta: float = 0.3, seed: int = 1) -> Cloud:
    """A geometry filled with particles as ``vrsph cloud --geometry`` does: a 2D GeoJSON Polygon
    or MultiPolygon (holes; a ring inside a hole bounds a filled island) or a 3D closed surface (STL, OFF, OBJ); fill "uniform", "perturbed" (delta) or "blue-noise"."""
    return _vrsph._geometry(str(path), float(spacing), fill, float(delta), int(seed))
