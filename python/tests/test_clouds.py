# SPDX-License-Identifier: BSD-3-Clause
"""Clouds from the families, arrays, files and geometries; numpy views; bad arrays refused."""
import os

import numpy as np
import pytest

import vrsph
from conftest import needs


@needs("CGAL")  # the centroid family
def test_families_match_the_cli(cli, tmp_path):
    for family, make in (("uniform", lambda: vrsph.cloud.lattice(dim=2, n=12)),
                         ("perturbed", lambda: vrsph.cloud.perturbed(dim=2, n=12, seed=4)),
                         ("centroids", lambda: vrsph.cloud.centroids(dim=2, n=12, seed=4)),
                         ("disk", lambda: vrsph.cloud.disk(dim=2, n=12))):
        path = str(tmp_path / f"{family}.csv")
        cli("cloud", "--family", family, "--n", "12", "--seed", "4", "--output", path)
        mine, theirs = make(), vrsph.read_cloud(path)
        assert len(mine) == len(theirs)
        assert np.array_equal(mine.tags, theirs.tags)
        assert np.allclose(mine.points, theirs.points, rtol=0, atol=1e-15)


def test_views_are_read_only_and_share_the_cloud_memory():
    c = vrsph.cloud.perturbed(dim=3, n=4, seed=2)
    p = c.points
    assert p.shape == (125, 3) and p.dtype == np.float64
    assert not p.flags.writeable and not c.tags.flags.writeable
    assert np.shares_memory(p, c.points)  # the same C++ array, no copy
    with pytest.raises(ValueError):
        p[0, 0] = 1.0
    assert c.normals is not None and c.normals.shape == (125, 3)
    assert c.count(vrsph.DIRICHLET) == 125 - 27
    assert c.spacing == pytest.approx(0.25)


def test_from_arrays_and_its_bad_input():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.5]])
    c = vrsph.cloud.from_arrays(pts, [1, 1, 1, 0])
    assert c.dim == 2 and len(c) == 4 and c.normals is None
    c = vrsph.cloud.from_arrays(np.asfortranarray(pts), np.array([2, 1, 1, 0], dtype=np.int8),
                                normals=np.array([[0.0, -1.0], [0, 0], [0, 0], [0, 0]]))
    assert c.normals[0].tolist() == [0.0, -1.0]  # a non-contiguous array is accepted (copied)
    cases = [
        ((pts.astype(int), [1, 1, 1, 0]), vrsph.InputError, "expected a float array"),
        ((np.zeros((4, 4)), [1, 1, 1, 0]), vrsph.InputError, "expected shape (N, d) with d = 1, 2 or 3, got (4, 4)"),
        ((pts, [1, 1, 7, 0]), vrsph.InputError, "particle 2 has tag 7"),
        ((pts, [1, 1, 1]), vrsph.InputError, "tags: expected shape (4,)"),
        ((pts, ["a", "b", "c", "d"]), vrsph.InputError, "expected an integer array"),
        ((np.zeros((0, 2)), np.zeros(0, dtype=int)), vrsph.InputError, "point cloud is empty"),
        ((np.array([[0.0, np.nan], [1, 0], [0, 1], [0.5, 0.5]]), [1, 1, 1, 0]), vrsph.InputError, "non-finite coordinate y = nan"),
    ]
    for args, error, message in cases:
        with pytest.raises(error) as e:
            vrsph.cloud.from_arrays(*args)
        assert message in str(e.value), str(e.value)
    with pytest.raises(vrsph.InputError, match="no outward normal"):  # a Neumann particle without a normal
        vrsph.cloud.from_arrays(pts, [2, 1, 1, 0], normals=np.zeros((4, 2)))


@needs("CGAL")  # the covering radius in 2D
def test_read_cloud_fields_and_geometries(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("x,y,tag,k\n0,0,1,2\n1,0,1,3\n0,1,1,4\n0.4,0.4,0,5\n")
    c = vrsph.read_cloud(str(path))
    assert c.fields["k"].tolist() == [2, 3, 4, 5]
    with pytest.raises(vrsph.IoError, match="cannot open"):
        vrsph.read_cloud(str(tmp_path / "missing.csv"))
    geo = tmp_path / "square.geojson"
    geo.write_text('{"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1],[0,1],[0,0]]]}')
    g = vrsph.cloud.from_geometry(str(geo), 0.1, fill="blue-noise")
    assert g.dim == 2 and g.count(vrsph.DIRICHLET) == 40 and g.count(vrsph.INTERIOR) > 60
    cr = vrsph.covering_radius(vrsph.cloud.lattice(dim=2, n=10))
    assert cr["radius"] == pytest.approx(np.sqrt(2) / 20)


def test_free_surface_of_a_disk_agrees_with_the_cli(cli, tmp_path):
    c = vrsph.cloud.disk(dim=2, n=20)
    fs = vrsph.free_surface(c)
    # The disk's particles on the circle, and only they, are its surface; normals point outwards.
    assert np.array_equal(fs["surface"], c.tags == vrsph.DIRICHLET)
    assert fs["count"] == int(np.sum(c.tags == vrsph.DIRICHLET))
    out = c.points[fs["surface"]] - 0.5  # the disk's centre is (1/2, 1/2)
    radial = out / np.linalg.norm(out, axis=1)[:, None]
    assert np.min(np.sum(fs["normals"][fs["surface"]] * radial, axis=1)) > 0.99
    assert fs["normals"].shape == (len(c), 2)
    path = str(tmp_path / "s.csv")
    cli("cloud", "--family", "disk", "--n", "20", "--free-surface", "--output", path)
    flags = np.loadtxt(path, delimiter=",", skiprows=1, usecols=7)
    assert np.array_equal(flags.astype(bool), fs["surface"])
    nd = vrsph.free_surface(c, criterion="number-density", density_threshold=0.9)
    assert nd["count"] > 0 and "density_ratio" in nd
    with pytest.raises(vrsph.ConfigError, match="must lie in"):
        vrsph.free_surface(c, density_threshold=1.2)
    with pytest.raises(vrsph.ConfigError, match="unknown free-surface criterion"):
        vrsph.free_surface(c, criterion="density")


def test_a_droplet_over_the_water_does_not_hide_its_surface():
    # A block of water (lattice, dx = 1/20) with a droplet 1.5 dx above its flat top: the top row
    # is surface under the droplet too; Marrone's scan as published lets the droplet cover it.
    dx = 0.05
    xs, ys = np.meshgrid(np.arange(21) * dx, np.arange(11) * dx)
    block = np.c_[xs.ravel(), ys.ravel()]
    points = np.vstack([block, [[0.5, 0.5 + 1.5 * dx]]])
    c = vrsph.cloud.from_arrays(points, np.full(len(points), vrsph.INTERIOR))
    under = np.flatnonzero((np.abs(block[:, 0] - 0.5) < 1.1 * dx) & (block[:, 1] > 0.5 - 1e-9))
    assert len(under) == 3
    assert vrsph.free_surface(c)["surface"][under].all()
    assert not vrsph.free_surface(c, scan_every_neighbour=True)["surface"][under].any()
