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
