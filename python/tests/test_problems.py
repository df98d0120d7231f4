# SPDX-License-Identifier: BSD-3-Clause
"""solve() and study(): equal to the CLI, data as strings/arrays/callables, every exception type."""
import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

import vrsph

U = "exp(x)*sin(y) + x*y"


def test_study_equals_the_cli_for_example_5(cli):
    rows = vrsph.study(problem="qw-ex5", methods=["vrsph"], cloud="perturbed", n=[20, 40], seeds=[1])
    theirs = cli("study", "--problem", "qw-ex5", "--method", "vrsph", "--cloud", "perturbed", "--n", "20,40",
                 "--seed", "1", "--format", "json")["rows"]
    assert [r["n"] for r in rows] == [20, 40]
    for a, b in zip(rows, theirs):
        assert set(b) <= set(a)  # the CLI's fields
        for key in ("error_inf", "error_l2", "order_inf", "h", "N", "unknowns", "mmatrix", "infeasible"):
            if isinstance(b[key], float):
                assert a[key] == pytest.approx(b[key], rel=1e-12, abs=0), key
            else:
                assert a[key] == b[key], key
    report = vrsph.study_report(problem="qw-ex5", methods="vrsph", cloud="uniform", n=[20, 40])
    assert report["fitted_order_inf"]["vrsph"] > 2.4  # compact rows (the default): O(h^3), 2.5 at n = 20 -> 40
    report = vrsph.study_report(problem="qw-ex5", methods="vrsph", cloud="uniform", n=[20, 40],
                                method_options={"vrsph": {"profile": "qw"}})
    assert report["fitted_order_inf"]["vrsph"] == pytest.approx(2, abs=0.1)  # [QW]'s rows


def test_solve_equals_the_cli_on_a_file_cloud(cli, tmp_path):
    path = str(tmp_path / "c.csv")
    cli("cloud", "--family", "perturbed", "--n", "24", "--seed", "3", "--output", path)
    theirs = cli("solve", "--cloud-file", path, "--method", "vrsph", "--u", U, "--a", "1+x^2",
                 "--vtu", str(tmp_path / "u.vtu"), "--format", "json")["rows"][0]
    mine = vrsph.solve(vrsph.read_cloud(path), u=U, a="1+x^2")
    assert mine.error_inf == pytest.approx(theirs["error_inf"], rel=1e-12, abs=0)
    assert mine.mmatrix and mine.unknowns == theirs["unknowns"]


def test_data_as_strings_arrays_and_callables_agree():
    c = vrsph.cloud.perturbed(dim=2, n=20, seed=5)
    x, y = c.points.T
    exact = np.exp(x) * np.sin(y)
    by_string = vrsph.solve(c, f="0", g="exp(x)*sin(y)")
    by_array = vrsph.solve(c, f=np.zeros(len(c)), g=exact)
    by_callable = vrsph.solve(c, f=0.0, g=lambda x, y: np.exp(x) * np.sin(y))
    assert np.abs(by_string.u - by_array.u).max() < 1e-13
    assert np.abs(by_string.u - by_callable.u).max() < 1e-13
    assert np.abs(by_string.u - exact).max() < 1e-3
    assert "error_inf" not in by_string  # no exact solution given
    by_problem = vrsph.solve(vrsph.Problem(c, f=0.0, g="exp(x)*sin(y)"))
    assert np.array_equal(by_problem.u, by_string.u)
    with pytest.raises(vrsph.ConfigError, match="not both"):
        vrsph.solve(vrsph.Problem(c, f=0.0, g=0.0), f=1.0)


def test_neumann_data_and_a_pure_neumann_problem():
    # The unit square, Neumann everywhere, u fixed at one particle.
    c0 = vrsph.cloud.lattice(dim=2, n=32)
    tags = np.where(c0.tags == vrsph.DIRICHLET, vrsph.NEUMANN, c0.tags)
    c = vrsph.cloud.from_arrays(c0.points.copy(), tags, normals=c0.normals.copy())
    r = vrsph.solve(c, u="cos(pi*x)*cos(pi*y)", method="fpm", options={"gradient_order": 2}, fix_constant=True)
    assert r.error_inf < 2e-2  # 7.2e-3 measured


def test_exceptions_keep_the_library_message_and_have_fitting_types():
    c = vrsph.cloud.perturbed(dim=2, n=10, seed=1)
    with pytest.raises(vrsph.ConfigError, match="unknown method 'nope'"):
        vrsph.solve(c, u=U, method="nope")
    with pytest.raises(vrsph.InputError, match="cannot parse expression .exp\\(x.: Missing parenthesis"):
        vrsph.solve(c, u="exp(x")
    with pytest.raises(vrsph.NumericalError) as e:  # perturbed, [QW]'s rows: infeasible rows next to the wall
        vrsph.solve(c, u=U, on_infeasible="error", options={"profile": "qw"})
    assert isinstance(e.value, RuntimeError) and isinstance(e.value, vrsph.Error)
    sparse = vrsph.cloud.from_arrays(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.2, 0.2], [0.9, 0.9]]),
                                     [1, 1, 1, 0, 1])
    with pytest.raises(vrsph.GeometryError):
        vrsph.solve(sparse, u=U, h=0.05)
    with pytest.raises(vrsph.InputError, match=r"f: the callable returned shape \(3,\)"):
        vrsph.solve(c, f=lambda x, y: np.zeros(3), g=0.0)

    class Boom(Exception):
        pass

    def boom(x, y):
        raise Boom("from the user's coefficient")

    with pytest.raises(Boom, match="from the user's coefficient"):
        vrsph.solve(c, a=boom, f=1.0, g=0.0)
    with pytest.raises(vrsph.InputError, match="not positive|a must be"):
        vrsph.solve(c, a=-np.ones(len(c)), f=1.0, g=0.0)
    with pytest.raises(vrsph.InputError, match="not finite"):
        vrsph.solve(c, f=np.full(len(c), np.nan), g=0.0)
    with pytest.raises(vrsph.InputError, match="f: expected an array of numbers"):
        vrsph.solve(c, f=np.array(["a"] * len(c)), g=0.0)
    with pytest.raises(vrsph.InputError, match=r"g: expected shape \(121,\), got \(121, 1\)"):
        vrsph.solve(c, f=0.0, g=np.zeros((len(c), 1)))


def test_spe_schemes_with_a_diagonal_mobility_and_the_spe_problems(cli, tmp_path):
    # A tensor mobility through solve() equals the CLI's --cloud-file --mobility, and the [SPE]
    # problems get their defaults (layout B, f, kernel) as `vrsph study` gives them.
    path = str(tmp_path / "c.csv")
    cli("cloud", "--family", "perturbed", "--n", "20", "--seed", "2", "--delta", "0.2", "--output", path)
    theirs = cli("solve", "--cloud-file", path, "--method", "m-sph", "--u", U, "--mobility", "1+x*x,2+y",
                 "--kernel", "cubic-spe", "--vtu", str(tmp_path / "u.vtu"), "--format", "json")["rows"][0]
    mine = vrsph.solve(vrsph.read_cloud(path), u=U, mobility=["1+x*x", "2+y"], method="m-sph", kernel="cubic-spe")
    assert mine.error_inf == pytest.approx(theirs["error_inf"], rel=1e-12, abs=0)
    assert mine.error_inf < 1e-3
    with pytest.raises(vrsph.ConfigError, match="cannot take a tensor"):
        vrsph.solve(vrsph.read_cloud(path), u=U, mobility=["1", "2"], method="fpm")
    rows = vrsph.study(problem="spe-mixed", methods=["s-sph", "m-sph"], n=[5, 10], h_factor=1.001)
    cli_rows = cli("study", "--problem", "spe-mixed", "--method", "s-sph,m-sph", "--n", "5,10", "--h-factor", "1.001",
                   "--format", "json")["rows"]
    for a, b in zip(rows, cli_rows):
        assert a["dof"] == b["dof"] and a["error_rel"] == pytest.approx(b["error_rel"], rel=1e-12)
    assert rows[0]["error_rel"] == pytest.approx(4.1e-3, rel=0.05)  # METHODS R15


def test_study_robin_faces_exact_on_linears():
    rows = vrsph.study(u="1 + x + 2*y", methods=["fpm"], method_options={"fpm": {"gradient_order": 2}}, n=[10],
                       robin=["all"], beta="1 + x*y")
    assert rows[0]["error_inf"] < 1e-9


def _with_neumann_faces(c, faces=("x1", "y1")):
    """The perturbed unit square with its x = 1 and y = 1 faces (corners excluded) as Neumann."""
    p, tags = c.points, np.array(c.tags)
    normals = np.zeros_like(p)
    for i, (x, y) in enumerate(p[:, :2]):
        if tags[i] != vrsph.DIRICHLET or min(x, y) < 1e-12 or (x > 1 - 1e-12 and y > 1 - 1e-12):
            continue
        if "x1" in faces and x > 1 - 1e-12:
            tags[i], normals[i] = vrsph.NEUMANN, (1, 0)
        elif "y1" in faces and y > 1 - 1e-12:
            tags[i], normals[i] = vrsph.NEUMANN, (0, 1)
    return vrsph.cloud.from_arrays(p[:, :2], tags, normals[:, :2])


def test_robin_data_and_the_assembled_system():
    # Issue 30: Robin data a du/dn + beta u = q; the system A x = b and the balance rows' wall flux.
    u = "exp(x)*sin(2*y)+x^2"
    errors = []
    for n in (32, 64):  # (16 -> 32 is pre-asymptotic: 3.9e-5 -> 1.2e-5, then 1.8e-6 and 1.6e-7 at 64, 128)
        c = _with_neumann_faces(vrsph.cloud.perturbed(dim=2, n=n, seed=2))
        s = vrsph.solve(c, u=u, robin=lambda x, y: 1 + x * y, return_system=True)
        errors.append(s.error_inf)
        assert s.mmatrix
        A, b, dofs = s.system["matrix"], s.system["rhs"], s.system["dofs"]
        assert isinstance(A, scipy.sparse.csr_matrix) and A.shape == (len(dofs), len(dofs)) and b.shape == (len(dofs),)
        x = scipy.sparse.linalg.spsolve(A.tocsc(), b)
        assert np.abs(x - s.u[dofs]).max() < 1e-8 * max(1, np.abs(x).max())  # the system that was solved
        neumann = np.array(c.tags) == vrsph.NEUMANN
        assert (s.wall_flux[neumann] > 0).all() and (s.wall_flux[~neumann] == 0).all()  # balance rows (default)
        assert isinstance(s.operator_rows, scipy.sparse.csr_matrix)
    assert np.log2(errors[0] / errors[1]) > 1.8  # second order or better with Robin faces
    with pytest.raises(vrsph.InputError, match="robin: beta = -1"):
        vrsph.solve(_with_neumann_faces(vrsph.cloud.perturbed(dim=2, n=8, seed=2)), u=u, robin=-1.0)


def test_error_texts_name_python_parameters():
    c = _with_neumann_faces(vrsph.cloud.perturbed(dim=2, n=8, seed=2))
    with pytest.raises(vrsph.ConfigError) as e:
        vrsph.solve(c, f=0.0, g=0.0)  # Neumann particles, no q and no u
    assert "parameter q" in str(e.value) and "--q" not in str(e.value)
