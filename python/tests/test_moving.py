# SPDX-License-Identifier: BSD-3-Clause
"""Operators on moving particles from Python: update(positions) gives the operators of a fresh
stencil() on the same positions (bitwise without the warm start; with it the same moment
conditions, so exact on quadratics), vector operators from the kept stencils, and refusals."""
import numpy as np
import pytest

import vrsph


def _move(x, dt):
    y = x.copy()
    inside = (x > 1e-12).all(axis=1) & (x < 1 - 1e-12).all(axis=1)
    u = np.sin(np.pi * x[:, 0]) * np.cos(np.pi * x[:, 1])
    v = -np.cos(np.pi * x[:, 0]) * np.sin(np.pi * x[:, 1])
    y[inside, 0] += dt * u[inside]
    y[inside, 1] += dt * v[inside]
    return y


def _same_nonzeros(a, b):
    a, b = a.tocsr(copy=True), b.tocsr(copy=True)
    a.eliminate_zeros()
    b.eliminate_zeros()
    assert (a != b).nnz == 0


def test_update_without_warm_start_equals_a_fresh_stencil():
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    ops = vrsph.Operators(c, method="vrsph", operators=("laplacian", "divergence"), warm_start=False)
    x = np.asarray(c.points)
    for _ in range(4):
        x = _move(x, 0.01)
        ops.update(x)
        moved = vrsph.cloud.from_arrays(x, c.tags, c.normals)
        fresh = vrsph.stencil(moved, method="vrsph", operator="laplacian", h=ops.radius)
        _same_nonzeros(ops.stencil("laplacian"), fresh)
    assert ops.stats["updates"] == 4
    assert ops.stats["searches"] < 5


def test_warm_updates_stay_exact_on_quadratics_and_linear_fields():
    c = vrsph.cloud.perturbed(dim=2, n=24, seed=5)
    ops = vrsph.Operators(c, operators=("laplacian", "divergence", "curl", "grad-div"))
    x = np.asarray(c.points)
    hits = rows = 0
    for _ in range(3):
        x = _move(x, 0.004)  # at most 0.1 dx per step
        ops.update(x)
        hits += ops.stats["warm_hits"]
        rows += ops.stats["warm_rows"]
    assert hits > 0.9 * rows
    p = ops.positions
    interior = (p > 0.2).all(axis=1) & (p < 0.8).all(axis=1)
    q = p[:, 0] ** 2 + p[:, 0] * p[:, 1] + 2 * p[:, 1] ** 2  # Laplacian 6
    assert np.max(np.abs(ops.apply("laplacian", q)[interior] - 6)) < 1e-6
    U = np.column_stack([2 * p[:, 0] + p[:, 1], 3 * p[:, 0] - p[:, 1]])  # div 1, curl 3 - 1 = 2
    assert np.max(np.abs(ops.apply("divergence", U)[interior] - 1)) < 1e-7
    assert np.max(np.abs(ops.apply("curl", U)[interior] - 2)) < 1e-7
    gd = ops.apply("grad-div", U)  # the Hessian rows are exact on quadratics at every particle (corners too)
    assert gd.shape == (len(p), 2) and np.max(np.abs(gd)) < 1e-6
    gdc = ops.apply("grad-div-composed", U)  # div U = 1: its gradient 0 where the rows read only exact values
    deep = (p > 0.35).all(axis=1) & (p < 0.65).all(axis=1)
    assert gdc.shape == (len(p), 2) and np.max(np.abs(gdc[deep])) < 1e-6
    for name in ("grad-div", "grad-div-composed"):
        M = vrsph.stencil(vrsph.cloud.from_arrays(p, np.asarray(c.tags), c.normals), operator=name, h=ops.radius)
        assert len(M) == 2 and len(M[0]) == 2


def test_hessian_rows_are_exact_on_quartics_and_give_grad_div():
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    p = np.asarray(c.points)
    x, y = p[:, 0], p[:, 1]
    H = vrsph.stencil(c, method="sph", operator="hessian")  # the same rows for every method
    assert len(H) == 3
    # Rows whose support is whole are exact on quartics; a face's half support (about 14 inside
    # 3 dx, as many as a quartic's monomials) on cubics; a corner's (8) on quadratics.
    corners = np.array([[0, 0], [0, 1], [1, 0], [1, 1]])
    far = np.min(np.linalg.norm(p[:, None, :] - corners[None], axis=2), axis=1) > 0.2
    inner = (p > 0.16).all(axis=1) & (p < 0.84).all(axis=1)
    u = x**4 + x**2 * y**2 + y**3
    exact = (12 * x**2 + 2 * y**2, 4 * x * y, 2 * x**2 + 6 * y)  # xx, xy, yy
    cubic = x**3 - 2 * x**2 * y + y**3
    for k, want in enumerate((6 * x - 4 * y, -4 * x, 6 * y)):
        assert np.max(np.abs(H[k] @ u - exact[k])[inner]) < 1e-8 * np.max(np.abs(exact[k]))
        assert np.max(np.abs(H[k] @ cubic - want)[far]) < 1e-6
    q = x**2 - 3 * x * y + 2 * y**2
    for k, want in enumerate((2, -3, 4)):
        assert np.max(np.abs(H[k] @ q - want)) < 1e-6
    U = np.column_stack([x**3, x * y**2])  # div U = 3x² + 2xy: grad (6x + 2y, 2x)
    ops = vrsph.Operators(c, operators=("hessian", "grad-div"))
    want = np.column_stack([6 * x + 2 * y, 2 * x])
    assert np.max(np.abs(ops.apply("grad-div", U) - want)[far]) < 1e-7
    M = vrsph.stencil(c, operator="grad-div")
    got = np.column_stack([M[b][0] @ U[:, 0] + M[b][1] @ U[:, 1] for b in range(2)])
    assert np.max(np.abs(got - want)[far]) < 1e-7


def test_bad_updates_are_refused_and_change_nothing():
    c = vrsph.cloud.perturbed(dim=2, n=12)
    ops = vrsph.Operators(c)
    before = ops.stencil("laplacian").copy()
    x = np.asarray(c.points)
    with pytest.raises(vrsph.InputError, match="cannot be added or removed"):
        ops.update(x[:-1])
    with pytest.raises(vrsph.InputError, match=r"shape \(169, 1\)"):
        ops.update(x[:, :1])
    with pytest.raises(vrsph.InputError, match=r"shape \(338,\) for 169 particles"):  # a flat array, said as numpy says it
        ops.update(x.ravel())
    with pytest.raises(vrsph.ArgumentTypeError, match="positions"):
        ops.update("abc")
    bad = x.copy()
    bad[3, 0] = np.nan
    with pytest.raises(vrsph.InputError, match="non-finite"):
        ops.update(bad)
    assert (ops.stencil("laplacian") != before).nnz == 0
    with pytest.raises(vrsph.ConfigError, match="give at most 2"):
        vrsph.Operators(c, skin=5)
    with pytest.raises(vrsph.ConfigError, match="div-a-grad"):
        vrsph.Operators(c, operators="div-a-grad")
    with pytest.raises(vrsph.ConfigError, match="no gradient stencil kept"):
        vrsph.Operators(c, operators="laplacian").stencil("divergence")


def test_a_periodic_box_keeps_the_warm_start_across_the_faces():
    c = vrsph.cloud.perturbed(dim=2, n=32, periodic="x,y", seed=2)
    ops = vrsph.Operators(c, operators=("laplacian", "divergence"))
    x = np.asarray(c.points).copy()
    for _ in range(3):  # a drift across the faces
        x[:, 0] = np.mod(x[:, 0] + 0.003 * (1 + np.sin(2 * np.pi * x[:, 1])), 1.0)
        ops.update(x)
    assert ops.stats["warm_hits"] > 0.9 * ops.stats["warm_rows"] > 0
    assert ops.stats["borrowed_rows"] > 0.8 * len(x)  # the divergence's gradient rows take the Laplacian's volumes
    own = vrsph.Operators(c, operators=("laplacian", "divergence"), share_volumes=False)
    own.update(x)
    assert own.stats["borrowed_rows"] == 0
    p = ops.positions
    u = np.sin(2 * np.pi * p[:, 0]) * np.cos(2 * np.pi * p[:, 1])
    err = np.max(np.abs(ops.apply("laplacian", u) + 8 * np.pi ** 2 * u))
    assert err < 0.05 * 8 * np.pi ** 2  # no face is a boundary
    U = np.column_stack([np.sin(2 * np.pi * p[:, 1]), np.cos(2 * np.pi * p[:, 0])])  # divergence-free
    assert np.max(np.abs(ops.apply("divergence", U))) < 0.05 * 2 * np.pi


def test_wrap_moves_particles_back_into_the_box_along_its_periodic_axes_only():
    c = vrsph.cloud.perturbed(dim=2, n=16, periodic="x", seed=4)
    ops = vrsph.Operators(c)
    w = ops.wrap(np.array([[1.1, 0.5], [-0.75, 1.2], [-2.75, -0.3], [0.999, 0.9]]))
    np.testing.assert_allclose(w, [[0.1, 0.5], [0.25, 1.2], [0.25, -0.3], [0.999, 0.9]], atol=1e-15)
    np.testing.assert_array_equal(ops.wrap(w), w)  # idempotent; y (not periodic) left for update to judge
    x = np.asarray(c.points) + [0.3, 0.0]  # a drift across the x faces
    with pytest.raises(vrsph.InputError, match="outside the periodic box.*Operators.wrap"):
        ops.update(x)
    ops.update(ops.wrap(x))
    assert np.all((ops.positions[:, 0] >= 0) & (ops.positions[:, 0] < 1))
    np.testing.assert_allclose(ops.positions[:, 0], np.mod(x[:, 0], 1.0), atol=1e-15)
    with pytest.raises(vrsph.InputError, match="wrap: positions must be an \\(N, 2\\) array"):
        ops.wrap(np.zeros((3, 3)))
    with pytest.raises(vrsph.InputError, match="wrap: particle 1 has a coordinate that is not finite"):
        ops.wrap(np.array([[0.1, 0.1], [np.nan, 0.2]]))
    with pytest.raises(vrsph.InputError, match="wrap: particle 0 at x = 1e.300 is more than 2.52 periods from the box"):
        ops.wrap(np.array([[1e300, 0.1]]))
    np.testing.assert_array_equal(ops.wrap([[0.5, 1e300]]), [[0.5, 1e300]])  # y is not periodic: left to update


def test_support_isotropy_is_one_inside_a_lattice_and_falls_when_it_is_stretched():
    c = vrsph.cloud.lattice(dim=2, n=20)
    ops = vrsph.Operators(c)
    iso = ops.support_isotropy()
    x = np.asarray(c.points)[:, :2]
    h = ops.radius
    inside = ((x > h - 1e-12) & (x < 1 - h + 1e-12)).all(axis=1)
    assert iso.shape == (len(c),)
    assert np.allclose(iso[inside], 1.0, atol=1e-12)
    assert iso.min() > 0.3  # faces and corners: the row along a face counts along it only
    # Pressed by 4 along y (a saddle point's inflow) with a radius below the columns' spacing: every
    # support holds only its own column, a line, and the ratio is 0; pressing alone keeps the
    # supports full (the default radius reaches the next columns): the ratio stays near 1.
    z = np.column_stack([x[:, 0], 0.5 + (x[:, 1] - 0.5) / 4])
    pressed = vrsph.cloud.from_arrays(z, c.tags, c.normals)
    assert vrsph.Operators(pressed, h=0.9 / 20).support_isotropy().max() == 0.0
    ops.update(z[:, :2])
    middle = (np.abs(x[:, 0] - 0.5) < 0.5 - h) & (np.abs(x[:, 1] - 0.5) < 0.25)
    assert middle.sum() > 10
    assert ops.support_isotropy()[middle].min() > 0.8  # 0.83: five columns within 3 dx


def test_per_particle_radii_reach_the_rows():
    # Larger radii for half the particles: after the next update their rows change (they reach
    # further), the others' rows are what they were; bad radii are refused and change nothing.
    c = vrsph.cloud.perturbed(dim=2, n=16, seed=3)
    ops = vrsph.Operators(c, operators=("laplacian",), warm_start=False)
    x = np.asarray(c.points)
    ops.update(x)
    before = ops.stencil("laplacian").copy()
    radii = np.full(len(c), ops.radius)
    radii[::2] *= 1.5
    ops.set_support_radii(radii)
    assert np.array_equal(ops.support_radii, radii)
    ops.update(x)
    after = ops.stencil("laplacian")
    assert np.array_equal(after[1::2].toarray(), before[1::2].toarray())
    assert not np.array_equal(after[::2].toarray(), before[::2].toarray())
    with pytest.raises(vrsph.InputError, match="radii for"):
        ops.set_support_radii([1.0])
    bad = radii.copy()
    bad[5] = -1.0
    with pytest.raises(vrsph.InputError, match="particle 5 must be positive and finite"):
        ops.set_support_radii(bad)
    assert np.array_equal(ops.support_radii, radii)


def test_div_a_grad_moves_with_its_coefficient():
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    x = np.asarray(c.points)
    a = 1 + 0.5 * np.sin(3 * x[:, 0]) * np.cos(2 * x[:, 1])
    ops = vrsph.Operators(c, operators=("laplacian", "div-a-grad"), coefficient=lambda x, y: 1 + 0.5 * np.sin(3 * x) * np.cos(2 * y),
                          warm_start=False)
    assert np.array_equal(ops.coefficient, a)
    for step in range(3):
        x = _move(x, 0.01)
        if step == 1:
            a = 2.0 + x[:, 0]  # a new coefficient with the new places
            ops.update(x, coefficient=a)
        else:
            ops.update(x)  # a stays with its particles
        moved = vrsph.cloud.from_arrays(x, c.tags, c.normals)
        fresh = vrsph.stencil(moved, operator="div-a-grad", coefficient=a, h=ops.radius)
        _same_nonzeros(ops.stencil("div-a-grad"), fresh)
    ops.set_coefficient(3.0)  # a number: every particle
    assert np.all(ops.coefficient == 3.0)
    moved = vrsph.cloud.from_arrays(x, c.tags, c.normals)
    lap = vrsph.stencil(moved, operator="laplacian", h=ops.radius)
    assert abs(ops.stencil("div-a-grad") - 3 * lap).max() < 1e-9 * abs(lap).max()
    # Refusals name the problem and change nothing.
    before = ops.stencil("div-a-grad").copy()
    with pytest.raises(vrsph.InputError, match="at particle 4"):
        bad = np.full(len(x), 1.0)
        bad[4] = -1
        ops.update(_move(x, 0.01), coefficient=bad)
    with pytest.raises(vrsph.InputError, match="expected shape"):
        ops.set_coefficient(np.ones(3))
    _same_nonzeros(ops.stencil("div-a-grad"), before)
    with pytest.raises(vrsph.ConfigError, match="needs the coefficient"):
        vrsph.Operators(c, operators=("div-a-grad",))
    with pytest.raises(vrsph.ConfigError, match="not among the operators"):
        vrsph.Operators(c, operators=("laplacian",), coefficient=1.0)
    with pytest.raises(vrsph.ConfigError, match="not kept"):
        vrsph.Operators(c).update(x, coefficient=np.ones(len(x)))


def test_the_callers_candidate_pairs_replace_the_verlet_list():
    scipy_spatial = pytest.importorskip("scipy.spatial")
    import scipy.sparse
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    own = vrsph.Operators(c, warm_start=False)
    given = vrsph.Operators(c, warm_start=False)
    x = np.asarray(c.points)
    for step in range(3):
        x = _move(x, 0.01)
        own.update(x)
        pairs = scipy_spatial.cKDTree(x).query_pairs(1.3 * own.radius, output_type="ndarray")  # wider than the support
        m = scipy.sparse.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(x), len(x)))
        given.update(x, neighbours=m + m.T)
        assert not given.stats["searched"]
        _same_nonzeros(given.stencil("laplacian"), own.stencil("laplacian"))
        for a, b in zip(given.stencil("gradient"), own.stencil("gradient")):
            _same_nonzeros(a, b)
    one_sided = (m + m.T).tolil()
    j = int(np.argmin(np.linalg.norm(x - x[200], axis=1) + 9 * (np.arange(len(x)) == 200)))  # 200's nearest
    one_sided[200, j] = 0  # the pair in row j only
    one_sided = one_sided.tocsr()
    one_sided.eliminate_zeros()
    before = given.stencil("laplacian").copy()
    with pytest.raises(vrsph.InputError, match="one-sided"):
        given.update(_move(x, 0.01), neighbours=one_sided)
    _same_nonzeros(given.stencil("laplacian"), before)


def test_a_coefficient_may_be_an_expression_at_the_particles_places():
    c = vrsph.cloud.perturbed(dim=2, n=10, seed=1)
    x = np.asarray(c.points)
    # stencil() as documented: values, a callable or an expression give the same rows.
    by_expression = vrsph.stencil(c, operator="div-a-grad", coefficient="1+x")
    by_values = vrsph.stencil(c, operator="div-a-grad", coefficient=1 + x[:, 0])
    assert abs(by_expression - by_values).max() == 0
    ops = vrsph.Operators(c, operators=("div-a-grad",), coefficient="1+x*y", warm_start=False)
    assert np.allclose(ops.coefficient, 1 + x[:, 0] * x[:, 1])
    y = _move(x, 0.01)
    ops.update(y, coefficient="2+x")  # evaluated at the new places
    assert np.allclose(ops.coefficient, 2 + y[:, 0])
    ops.set_coefficient("one-plus-r2")  # a catalogue name, as the CLI takes it
    assert np.allclose(ops.coefficient, 1 + (y ** 2).sum(axis=1))
    with pytest.raises(vrsph.InputError, match="cannot parse expression"):
        ops.set_coefficient("1+")
    with pytest.raises(vrsph.InputError, match="not finite"):
        ops.set_coefficient("sqrt(x-2)")
    assert np.allclose(ops.coefficient, 1 + (y ** 2).sum(axis=1))
