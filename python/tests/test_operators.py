# SPDX-License-Identifier: BSD-3-Clause
"""Stencils as SciPy matrices (no copy), exactness, diagnostics, the registry, the operator study."""
import numpy as np
import pytest
import scipy.sparse

import vrsph


def test_interface_of_the_issue():
    c = vrsph.cloud.perturbed(dim=2, n=40, seed=1)
    L = vrsph.stencil(c, method="vrsph", operator="laplacian", h_factor=3)
    assert isinstance(L, scipy.sparse.csr_matrix) and L.shape == (1681, 1681)
    # Issue 30: only the entries the rows use are stored (NNLS leaves most neighbours at v = 0):
    # nnz is the count of non-zeros (the diagonal included), about 10 per row, not the ~28 neighbours.
    assert L.nnz == np.count_nonzero(L.data)
    assert 1681 * 5 < L.nnz < 1681 * 14
    s = vrsph.stencil(c, method="vrsph", operator="laplacian", diagnostics=True)
    assert "point rows for operator values" in s.row_forms  # says which rows it took


def test_csr_arrays_are_the_librarys_and_gradient_components_have_no_explicit_zeros():
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    L = vrsph.stencil(c, method="vrsph", operator="laplacian")
    assert L.indices.dtype == np.int32 and not L.indices.flags.owndata  # SciPy kept our array
    assert not L.data.flags.owndata
    s = vrsph.stencil(c, method="vrsph", operator="gradient", diagnostics=True)
    gx, gy = s.matrices
    for g in (gx, gy):
        assert g.nnz == np.count_nonzero(g.data)
    x, y = c.points[:, 0], c.points[:, 1]
    interior = c.tags == vrsph.INTERIOR
    u = 2 * x - 3 * y + 1  # VRSPH's gradient is exact on linear fields
    assert np.abs((gx @ u)[interior] - 2).max() < 1e-9
    assert np.abs((gy @ u)[interior] + 3).max() < 1e-9
    assert s.residual is not None and s.residual.shape == (len(c),)


def test_vrsph_laplacian_is_exact_on_quadratics_and_minus_l_has_m_matrix_signs():
    c = vrsph.cloud.lattice(dim=2, n=16)
    L = vrsph.stencil(c, method="vrsph").tocoo()
    x, y = c.points.T
    interior = c.tags == vrsph.INTERIOR
    assert np.abs((L @ (x * x + 3 * y * y))[interior] - 8).max() < 1e-8
    off = L.row != L.col
    assert (L.data[off] >= 0).all() and (L.data[~off] <= 0).all()


def test_compact_rows_come_with_their_right_hand_side_weights():
    # vrsph rhs=compact: L u = M f with M a positive average (rows sum to 1); the plain call
    # refuses to hand back L alone, which would silently drop M.
    c = vrsph.cloud.perturbed(dim=2, n=16, seed=1)
    with pytest.raises(vrsph.ConfigError, match="right-hand-side weights"):
        vrsph.stencil(c, method="vrsph", options={"rhs": "compact"})
    s = vrsph.stencil(c, method="vrsph", options={"rhs": "compact"}, diagnostics=True)
    interior = c.tags == vrsph.INTERIOR
    M = s.rhs
    assert M is not None and M.shape == s.matrix.shape
    assert np.abs(np.asarray(M.sum(axis=1)).ravel()[interior] - 1).max() < 1e-12 and (M.data >= 0).all()
    x, y = c.points.T
    u = x ** 4 + x * y ** 3  # exact on quartics: L u = M (Laplacian u)
    lap = 12 * x ** 2 + 6 * x * y
    assert np.abs((s.matrix @ u - M @ lap)[interior]).max() < 1e-6
    assert vrsph.stencil(c, method="vrsph", diagnostics=True).rhs is None


def test_div_a_grad_takes_a_callable_coefficient_and_bad_arguments_raise():
    c = vrsph.cloud.lattice(dim=2, n=10)
    A = vrsph.stencil(c, method="sph", operator="div-a-grad", coefficient=lambda x, y: 1 + x * x)
    assert A.shape == (121, 121)
    with pytest.raises(vrsph.ConfigError, match="needs the coefficient"):
        vrsph.stencil(c, method="sph", operator="div-a-grad")
    with pytest.raises(vrsph.ConfigError, match="unknown method"):
        vrsph.stencil(c, method="nope")
    with pytest.raises(ValueError):  # ConfigError is a ValueError too
        vrsph.stencil(c, operator="jacobian")
    with pytest.raises(vrsph.InputError, match=r"coefficient: expected shape \(121,\)"):
        vrsph.stencil(c, method="sph", operator="div-a-grad", coefficient=np.ones(5))
    with pytest.raises(vrsph.ConfigError, match="exceeds the extent"):
        vrsph.stencil(c, h=100.0)


def test_registry_and_kernels():
    names = {m["name"]: m for m in vrsph.methods()}
    assert "vrsph" in names and "laplacian" in names["vrsph"]["operators"]
    assert names["vrsph"]["source"].startswith("[QW]")
    assert names["vrsph"]["reference"]["identifier"] == "arXiv:2503.15188"
    assert names["gpm"]["reference"]["authors"] == "Y. Imoto"
    assert {"cubic", "gaussian"} <= {k["name"] for k in vrsph.kernels()}


def test_operator_study_equals_the_cli(cli):
    mine = vrsph.operator_study(problem="qw-trunc", methods=["vrsph", "sph"], cloud="perturbed", n=[16, 32], seed=2)
    theirs = cli("operator", "--problem", "qw-trunc", "--method", "vrsph,sph", "--cloud", "perturbed",
                 "--n", "16,32", "--seed", "2", "--format", "json")
    assert len(mine["rows"]) == len(theirs["rows"]) == 4
    for a, b in zip(mine["rows"], theirs["rows"]):
        assert a["method"] == b["method"] and a["n"] == b["n"]
        assert a["error_inf"] == pytest.approx(b["error_inf"], rel=1e-12, abs=0)
        assert a["error_l2"] == pytest.approx(b["error_l2"], rel=1e-12, abs=0)


def test_the_gil_is_released_while_the_library_works():
    # A long stencil build in a worker thread: the main thread keeps running Python meanwhile
    # (with the GIL held by the worker it would advance only at the interpreter's switch interval).
    import sys
    import threading
    import time

    c = vrsph.cloud.perturbed(dim=2, n=400, seed=1)
    old = sys.getswitchinterval()
    sys.setswitchinterval(1.0)  # a GIL holder would block the main thread for up to 1 s at a time
    try:
        done = threading.Event()
        worker = threading.Thread(target=lambda: (vrsph.stencil(c, method="vrsph"), done.set()))
        ticks, start = 0, time.perf_counter()
        worker.start()
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)
        worker.join()
        elapsed = time.perf_counter() - start
    finally:
        sys.setswitchinterval(old)
    assert elapsed > 0.05
    assert ticks > 0.3 * elapsed / 0.0011, (ticks, elapsed)  # most of the 1 ms ticks happened


def test_a_cloud_caches_its_spacing_and_neighbours():
    # Issue 30: every call re-estimated the spacing (0.12 s at 1e5 particles) and searched the
    # neighbours again. Now computed once per Cloud; the stencils are the same.
    rng = np.random.default_rng(4)
    p = rng.random((4000, 2))
    c = vrsph.cloud.from_arrays(p, np.zeros(len(p), dtype=int))
    assert not hasattr(c, "_vrsph_cache")
    first = vrsph.stencil(c, method="sph")
    assert hasattr(c, "_vrsph_cache")
    again = vrsph.stencil(c, method="sph")
    assert (first != again).nnz == 0 and c.spacing == c.spacing
    fresh = vrsph.cloud.from_arrays(p, np.zeros(len(p), dtype=int))
    assert (vrsph.stencil(fresh, method="sph") != first).nnz == 0
    assert fresh.spacing == c.spacing
    # Positions cannot change behind the cache: the views are read-only and stay so.
    with pytest.raises(ValueError):
        c.points.setflags(write=True)
    with pytest.raises(vrsph.ConfigError, match="must be a vrsph.Cloud"):
        vrsph.stencil("not a cloud")


def _one_sided(pairs):
    """The list without row 0's first neighbour (that neighbour's row still lists 0)."""
    broken = pairs.tolil()
    broken[0, broken.rows[0][0]] = 0
    broken = broken.tocsr()
    broken.eliminate_zeros()
    return broken


def test_a_neighbour_list_of_the_callers_own():
    # Issue 33: a list kept by the caller (here SciPy's k-d tree) is accepted, distances computed
    # where missing; the stencil equals the one on the library's own search.
    scipy_spatial = pytest.importorskip("scipy.spatial")
    c = vrsph.cloud.perturbed(dim=2, n=24, seed=5)
    h = 3 * c.spacing
    pairs = scipy_spatial.cKDTree(c.points).sparse_distance_matrix(scipy_spatial.cKDTree(c.points), h * (1 - 1e-12),
                                                                    output_type="coo_matrix").tocsr()
    pairs.setdiag(0)
    pairs.eliminate_zeros()
    own = vrsph.stencil(c, method="vrsph", h=h)
    theirs = vrsph.stencil(c, method="vrsph", h=h, neighbours=pairs)
    assert abs(own - theirs).max() == 0
    with_distances = vrsph.stencil(c, method="vrsph", h=h, neighbours=(pairs.indptr, pairs.indices, pairs.data))
    assert abs(own - with_distances).max() == 0
    with pytest.raises(vrsph.InputError, match="does not list"):
        vrsph.stencil(c, method="vrsph", h=h, neighbours=_one_sided(pairs))
    with pytest.raises(vrsph.ArgumentTypeError, match="neighbours must be"):
        vrsph.stencil(c, method="vrsph", h=h, neighbours="all of them")
    with pytest.raises(vrsph.ArgumentTypeError, match="indices must be a 1D array of integers"):
        vrsph.stencil(c, method="vrsph", h=h, neighbours=(pairs.indptr, pairs.indices.astype(float)))


def test_a_neighbour_list_of_the_callers_own_on_a_periodic_box():
    # SciPy's periodic k-d tree (boxsize) lists the pairs across the faces; vrsph takes each to
    # the nearest image and builds the same rows as on its own minimum-image search.
    scipy_spatial = pytest.importorskip("scipy.spatial")
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=5, periodic="x,y")
    h = 3 * c.spacing
    tree = scipy_spatial.cKDTree(np.asarray(c.points), boxsize=[1.0, 1.0])
    pairs = tree.sparse_distance_matrix(tree, h * (1 - 1e-12), output_type="coo_matrix").tocsr()
    pairs.setdiag(0)
    pairs.eliminate_zeros()
    for method in ("vrsph", "fpm", "sph"):
        own = vrsph.stencil(c, method=method, h=h)
        theirs = vrsph.stencil(c, method=method, h=h, neighbours=(pairs.indptr, pairs.indices, pairs.data))
        assert abs(own - theirs).max() <= 1e-9 * abs(own).max(), method
    with pytest.raises(vrsph.InputError, match="does not list"):
        vrsph.stencil(c, method="fpm", h=h, neighbours=_one_sided(pairs))


def test_default_gradients_are_exact_on_cubics_and_the_published_rows_one_option_away():
    # VRSPH's and FPM's default gradient rows are raised to exactness on cubics (docs/methods.md,
    # "Gradient rows exact on cubics"); gradient_order=2 / 1 give [QW]'s rows, exact on
    # quadratics / linears only.
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=3)
    x, y = c.points[:, 0], c.points[:, 1]
    interior = c.tags == vrsph.INTERIOR
    u = x**3 - 2 * x * x * y + 3 * y**3 + x * y
    exact_x, exact_y = 3 * x * x - 4 * x * y + y, -2 * x * x + 9 * y * y + x
    for method, published in (("vrsph", 2), ("fpm", 1)):
        gx, gy = vrsph.stencil(c, method=method, operator="gradient", diagnostics=True).matrices
        assert np.abs((gx @ u - exact_x)[interior]).max() < 1e-8, method
        assert np.abs((gy @ u - exact_y)[interior]).max() < 1e-8, method
        px, _ = vrsph.stencil(c, method=method, operator="gradient", options={"gradient_order": published},
                              diagnostics=True).matrices
        assert np.abs((px @ u - exact_x)[interior]).max() > 1e-4, method
    with pytest.raises(vrsph.ConfigError, match="contradicts profile=qw"):
        vrsph.stencil(c, method="vrsph", operator="gradient", options={"profile": "qw", "gradient_order": 3})
