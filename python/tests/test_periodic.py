# SPDX-License-Identifier: BSD-3-Clause
"""Periodic boxes from Python: clouds with ``periodic=``, stencils across the faces, and a
fully periodic Poisson solve (zero mean, second order with VRSPH's point rows)."""
import numpy as np
import pytest

import vrsph

U = "sin(2*pi*x)*cos(2*pi*y)"


def test_a_periodic_lattice_has_no_boundary_particles():
    c = vrsph.cloud.perturbed(dim=2, n=16, periodic="all")
    assert len(c) == 256
    assert c.count(vrsph.INTERIOR) == 256
    c = vrsph.cloud.lattice(dim=2, n=16, periodic="x")
    assert len(c) == 16 * 17 and c.count(vrsph.DIRICHLET) == 32


def test_laplacian_across_the_faces_and_a_fully_periodic_solve():
    errors = []
    for n in (16, 32, 64):
        c = vrsph.cloud.perturbed(dim=2, n=n, periodic="x,y")
        L = vrsph.stencil(c, method="vrsph", operator="laplacian")
        x = np.asarray(c.points)
        u = np.sin(2 * np.pi * x[:, 0]) * np.cos(2 * np.pi * x[:, 1])
        lap = L @ u
        assert np.max(np.abs(lap + 8 * np.pi ** 2 * u)) < 0.1 * 8 * np.pi ** 2  # no face is a boundary
        r = vrsph.solve(c, u=U, method="vrsph", options={"rhs": "point"})
        assert abs(np.mean(r.u)) < 1e-12  # the constant: zero mean
        errors.append(r.error_inf)
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.9), errors


def test_bad_periodic_input():
    with pytest.raises(vrsph.ConfigError, match="periodic axes are x, y, z or all"):
        vrsph.cloud.perturbed(dim=2, n=8, periodic="w")
    c = vrsph.cloud.perturbed(dim=2, n=16, periodic="all")
    with pytest.raises(vrsph.InputError, match="zero mean"):
        vrsph.solve(c, f="1", g="0")


def test_vector_operators_from_the_gradient_and_laplacian_rows():
    c = vrsph.cloud.perturbed(dim=2, n=32, periodic="all")
    x = np.asarray(c.points)
    s, k = np.sin(2 * np.pi * x), np.cos(2 * np.pi * x)
    U = np.column_stack([s[:, 0] * k[:, 1], k[:, 0] * s[:, 1]])
    D = vrsph.stencil(c, operator="divergence")
    div = D[0] @ U[:, 0] + D[1] @ U[:, 1]
    C = vrsph.stencil(c, operator="curl")
    curl = C[0] @ U[:, 0] + C[1] @ U[:, 1]
    assert np.max(np.abs(div - 4 * np.pi * k[:, 0] * k[:, 1])) < 0.05 * 4 * np.pi
    assert np.max(np.abs(curl)) < 0.05 * 4 * np.pi  # this field's curl is 0
    L = vrsph.stencil(c, operator="vector-laplacian")
    assert np.max(np.abs(L @ U + 8 * np.pi ** 2 * U)) < 0.05 * 8 * np.pi ** 2


def test_own_particles_in_a_periodic_box_and_files_that_keep_it(tmp_path):
    # A user's particles in the box [0, 2) x [0, 1) (not the unit one), periodic along both axes:
    # the stencil sees across the faces, as for a generated periodic cloud.
    rng = np.random.default_rng(4)
    nx, ny = 64, 32
    gx, gy = np.meshgrid((np.arange(nx) + 0.5) * 2 / nx, (np.arange(ny) + 0.5) / ny, indexing="ij")
    pts = np.column_stack([gx.ravel(), gy.ravel()]) + rng.uniform(-0.2, 0.2, (nx * ny, 2)) / ny
    pts[:, 0] %= 2.0
    pts[:, 1] %= 1.0
    c = vrsph.cloud.from_arrays(pts, np.zeros(len(pts), dtype=int), periodic="x,y", box=([0, 0], [2, 1]))
    assert c.periodic == "x,y"
    lo, hi = c.box
    assert list(lo) == [0, 0] and list(hi) == [2, 1]
    u = np.sin(np.pi * pts[:, 0]) * np.cos(2 * np.pi * pts[:, 1])
    L = vrsph.stencil(c, operator="laplacian")
    assert np.max(np.abs(L @ u + 5 * np.pi ** 2 * u)) < 0.02 * 5 * np.pi ** 2  # no face is a boundary
    # The same particles without the box have faces: the rows there miss the neighbours across
    # them (0.94 of the Laplacian's scale against 0.008).
    plain = vrsph.cloud.from_arrays(pts, np.zeros(len(pts), dtype=int))
    assert plain.periodic == "" and plain.box is None
    L = vrsph.stencil(plain, operator="laplacian")
    assert np.max(np.abs(L @ u + 5 * np.pi ** 2 * u)) > 0.5 * 5 * np.pi ** 2
    # write_vtu records the box and read_cloud restores it, with the fields.
    path = str(tmp_path / "c.vtu")
    vrsph.write_vtu(path, c, {"u": u})
    r = vrsph.read_cloud(path)
    assert r.periodic == "x,y" and [list(v) for v in r.box] == [[0, 0], [2, 1]]
    assert np.array_equal(np.asarray(r.points), pts) and np.allclose(r.fields["u"], u)
    # A file whose box is not recorded: given on reading.
    csv = tmp_path / "c.csv"
    np.savetxt(csv, np.column_stack([pts, np.zeros(len(pts))]), delimiter=",", header="x,y,tag", comments="", fmt="%.17g")
    r = vrsph.read_cloud(str(csv), periodic="x,y", box=[0, 0, 2, 1])
    assert r.periodic == "x,y" and vrsph.read_cloud(str(csv)).periodic == ""


def test_bad_periodic_boxes():
    pts = np.array([[0.25, 0.25], [0.75, 0.75]])
    tags = [0, 0]
    with pytest.raises(vrsph.ConfigError, match="periodic= needs box="):
        vrsph.cloud.from_arrays(pts, tags, periodic="x")
    with pytest.raises(vrsph.ConfigError, match="box= needs periodic="):
        vrsph.cloud.from_arrays(pts, tags, box=([0, 0], [1, 1]))
    with pytest.raises(vrsph.ConfigError, match="expected \\(lo, hi\\) with 2 coordinates each"):
        vrsph.cloud.from_arrays(pts, tags, periodic="x", box=[0, 1])
    with pytest.raises(vrsph.InputError, match="lies outside the periodic box \\[0, 0.5\\) along x"):
        vrsph.cloud.from_arrays(pts, tags, periodic="x", box=([0, 0], [0.5, 1]))
    with pytest.raises(vrsph.InputError, match="upper corner must exceed the lower one along y"):
        vrsph.cloud.from_arrays(pts, tags, periodic="x", box=([0, 1], [1, 1]))
    with pytest.raises(vrsph.InputError, match="not a finite length"):
        vrsph.cloud.from_arrays(pts, tags, periodic="x", box=([0, 0], [np.inf, 1]))
    with pytest.raises(vrsph.ConfigError, match="periodic axis z does not exist in 2D"):
        vrsph.cloud.from_arrays(pts, tags, periodic="z", box=([0, 0], [1, 1]))
