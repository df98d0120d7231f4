# SPDX-License-Identifier: BSD-3-Clause
"""vrsph: accurate particle (SPH-family) discretisations of elliptic operators on irregular
point clouds, and Poisson-type boundary value problems on them.

A thin face of the C++ library: numpy arrays in, numpy arrays and ``scipy.sparse`` matrices
out (the CSR arrays are the library's own, not copies).

>>> import vrsph
>>> c = vrsph.cloud.perturbed(dim=2, n=40, seed=1)
>>> L = vrsph.stencil(c, method="vrsph", operator="laplacian", h_factor=3)
>>> r = vrsph.solve(c, u="sin(pi*x)*sin(pi*y)")        # f, g derived from u
>>> rows = vrsph.study(problem="qw-ex5", methods=["vrsph"], cloud="perturbed", n=[20, 40])

Errors are ``vrsph.Error`` subclasses that are also the fitting built-in exception:
``InputError`` / ``ConfigError`` / ``GeometryError`` (``ValueError``), ``IoError``
(``OSError``), ``NumericalError`` (``RuntimeError``), ``ResourceError`` (``MemoryError``),
``ArgumentTypeError`` (``TypeError``: an argument of the wrong type, named).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np
import scipy.sparse

from ._version import __version__, built_for_python

try:
    from . import _vrsph
except ImportError as _error:  # a compiled core for another interpreter, or none at all
    import sys as _sys

    raise ImportError(
        f"vrsph {__version__}: cannot load its compiled core vrsph._vrsph ({_error}); this package was built for "
        f"Python {built_for_python}, this is Python {_sys.version_info.major}.{_sys.version_info.minor}: rebuild it "
        "here (pip install --no-build-isolation . in the source tree)"
    ) from _error
if _vrsph.__version__ != __version__:
    raise ImportError(
        f"vrsph: the Python package is version {__version__} but its compiled core ({_vrsph.__file__}) is "
        f"{_vrsph.__version__}: two installations are mixed; reinstall one (pip install --force-reinstall "
        "--no-build-isolation .) or remove the other"
    )

from . import _args
from . import cloud
from ._args import ArgumentTypeError
from ._vrsph import (  # noqa: F401  (re-exported)
    DIRICHLET,
    GHOST,
    INTERIOR,
    NEUMANN,
    Cloud,
    ConfigError,
    Error,
    FeatureUnavailable,
    GeometryError,
    InputError,
    IoError,
    NumericalError,
    ResourceError,
    covering_radius,
    free_surface,
    kernels,
    methods,
    parts,
    write_vtu,
)

__all__ = [
    "Cloud", "cloud", "read_cloud", "methods", "kernels", "stencil", "Stencil", "Operators", "Flow", "taylor_green", "cavity", "hydrostatic", "dam_break", "Problem", "solve", "Solution", "study",
    "operator_study", "study_report", "covering_radius", "free_surface", "write_vtu", "Error", "InputError", "IoError", "ConfigError", "ResourceError",
    "ArgumentTypeError", "GeometryError", "NumericalError", "FeatureUnavailable", "parts", "__version__", "INTERIOR", "DIRICHLET", "NEUMANN", "GHOST",
]

Data = Union[None, str, float, Sequence[float], np.ndarray, Callable[..., Any]]


def read_cloud(path: str, dim: int = 0, periodic: str = "", box=None) -> Cloud:
    """Reads a cloud file (CSV, VTU/VTP, Gmsh .msh) as ``vrsph solve --cloud-file`` does.

    A periodic box the file records (``vrsph cloud --periodic ... --output`` and
    :func:`write_vtu` write it: a ``# vrsph domain:`` line before a CSV header, field data in a
    VTU) comes back with it; ``periodic=`` with ``box=(lo, hi)`` sets one instead (see
    :func:`vrsph.cloud.from_arrays`). The file's extra columns are in ``cloud.fields``
    ({name: (N,) array})."""
    c, fields = _vrsph._read_cloud(str(path), dim)
    c = cloud.with_periodic_box(c, periodic, box)
    c.fields = fields
    return c


class Stencil:
    """A method's operator on a cloud: ``matrix`` (scipy CSR; for the gradient ``matrices``, one
    per direction over one pattern) and the per-row diagnostics ``residual`` (local problem
    residual, or None), ``condition`` (local condition number, or None) and ``infeasible``
    (indices of rows whose local problem failed or exceeds the tolerance)."""

    def __init__(self, raw: dict, n: int):
        shape = (n, n)
        self.matrices = tuple(
            scipy.sparse.csr_matrix((data, raw["indices"], raw["indptr"]), shape=shape, copy=False)
            for data in raw["data"])
        if len(self.matrices) > 1:
            # The components share one pattern (kept where any of them is non-zero): each its
            # own copy without the others' zeros, so that nnz counts its non-zeros.
            self.matrices = tuple(m.copy() for m in self.matrices)
            for m in self.matrices:
                m.eliminate_zeros()
        # vrsph rhs=compact: the rows stand for Σ_k μ_ik (L u)(x_k); rhs is that averaging
        # operator (same pattern), so L u = rhs @ f is the discrete problem. None otherwise.
        self.rhs = None if raw.get("rhs") is None else scipy.sparse.csr_matrix(
            (raw["rhs"], raw["indices"], raw["indptr"]), shape=shape, copy=False)
        self.residual = raw["residual"]
        self.condition = raw["condition"]
        self.infeasible = raw["infeasible"]
        self.h = raw["h"]
        self.spacing = raw["spacing"]
        # The row forms the method's defaults chose for operator values (VRSPH: point rows;
        # solve() uses its compact and balance rows), "" when no option chose by the use.
        self.row_forms = raw.get("row_forms", "")

    @property
    def matrix(self) -> scipy.sparse.csr_matrix:
        if len(self.matrices) != 1:
            raise ConfigError(f"this stencil has {len(self.matrices)} components: use .matrices")
        return self.matrices[0]


def stencil(cloud: Cloud, method: str = "vrsph", operator: str = "laplacian", h: float | None = None,
            h_factor: float = 3.0, kernel: str = "cubic", options: Mapping[str, Any] | None = None,
            coefficient: Data = None, infeasible_tol: float = 1e-6, diagnostics: bool = False,
            neighbours: Any = None) -> "scipy.sparse.csr_matrix | tuple[scipy.sparse.csr_matrix, ...] | Stencil":
    """The stencil of ``method`` for ``operator`` (value, dx, dy, dz, gradient, laplacian,
    div-a-grad, hessian) on every non-ghost particle, as ``scipy.sparse.csr_matrix`` (N x N); the
    gradient as a tuple of ``dim`` matrices sharing one pattern, the Hessian as a tuple of
    dim (dim + 1) / 2 (the second derivatives xx, xy, yy; in 3D xx, xy, xz, yy, yz, zz), rows exact on
    polynomials of degree 4 built the same way for every method (on its neighbours and kernel).

    Vector fields U (N x dim), from the same rows: ``"divergence"`` gives the tuple D with
    div U = sum_c D[c] @ U[:, c] (the gradient's matrices); ``"curl"`` in 2D the tuple C with
    curl U = C[0] @ U[:, 0] + C[1] @ U[:, 1] (that is (-G_y, G_x)), in 3D the gradient's tuple
    G (curl U = (G_y U_z - G_z U_y, G_z U_x - G_x U_z, G_x U_y - G_y U_x)); ``"vector-laplacian"``
    the Laplacian L, applied to each component (L @ U); ``"grad-div"`` the tuple of tuples M with
    (grad div U)_b = sum_c M[b][c] @ U[:, c], M[b][c] the Hessian's d_b d_c rows;
    ``"grad-div-composed"`` the same from the method's gradient rows twice, M[b][c] = G_b @ G_c.

    The support radius is ``h`` if given, else ``h_factor`` x the cloud's spacing.
    ``coefficient`` (div-a-grad only): a in div(a grad u), as values, a callable of the
    coordinates or an expression. ``diagnostics=True`` returns the :class:`Stencil` instead.
    ``neighbours``: a list the caller already has instead of the library's search — ``(indptr,
    indices)``, ``(indptr, indices, distances)`` or a SciPy sparse matrix whose pattern is the
    list (rows in any order, no self); it is checked against the cloud and the support radius
    (every listed pair closer than it, pairs within both particles' radii in both rows, given
    distances equal to the positions'), distances are computed where missing. On a periodic
    box each listed pair is taken to the nearest image (e.g. SciPy's ``cKDTree(..., boxsize=...)``)."""
    _check_cloud(cloud)
    operator = _args.text(operator, "operator")
    if operator in _VECTOR_BASE:
        if diagnostics:
            raise ConfigError(f"diagnostics=True applies to the stencil itself: ask for operator {_VECTOR_BASE[operator]}")
        base = stencil(cloud, method, _VECTOR_BASE[operator], h, h_factor, kernel, options, coefficient, infeasible_tol,
                       False, neighbours)
        if operator == "curl":
            if cloud.dim == 1:
                raise ConfigError("the curl needs 2 or 3 dimensions, got 1")
            return (-base[1], base[0]) if cloud.dim == 2 else base
        if operator == "grad-div":
            return _grad_div_from_hessian(base, cloud.dim)
        if operator == "grad-div-composed":
            return tuple(tuple((gb @ gc).tocsr() for gc in base) for gb in base)
        return base
    user_list = _args.neighbour_list(neighbours, "neighbours", len(cloud))
    a = None
    if coefficient is not None:
        a = _values(cloud, coefficient, "coefficient")
    raw = _vrsph._stencil(cloud, _args.text(method, "method"), operator,
                          _args.optional_length(h, "h"), _args.number(h_factor, "h_factor", positive=True),
                          _args.text(kernel, "kernel"), _args.options(options, "options"), a,
                          _args.number(infeasible_tol, "infeasible_tol", positive=True), user_list)
    s = Stencil(raw, len(cloud))
    if diagnostics:
        return s
    if s.rhs is not None:
        raise ConfigError("these rows (vrsph rhs=compact) come with right-hand-side weights: L u = M f, not f; "
                          "call stencil(..., diagnostics=True) and use .matrix and .rhs")
    return s.matrices if operator in ("gradient", "hessian") else s.matrices[0]


_VECTOR_BASE = {"divergence": "gradient", "curl": "gradient", "vector-laplacian": "laplacian", "grad-div": "hessian",
                "grad-div-composed": "gradient"}


def _hessian_component(b: int, c: int, dim: int) -> int:
    """The Hessian tuple's entry holding d_b d_c (xx, xy, yy; xx, xy, xz, yy, yz, zz)."""
    b, c = min(b, c), max(b, c)
    return b * dim - b * (b - 1) // 2 + (c - b)


def _grad_div_from_hessian(hessian: tuple, dim: int) -> tuple:
    return tuple(tuple(hessian[_hessian_component(b, c, dim)] for c in range(dim)) for b in range(dim))


class Operators:
    """A method's stencils on particles that move: built once, then ``update(positions)`` every
    time step at a fraction of the cost of new stencils (the neighbour list kept with a Verlet
    skin, storage reused, VRSPH's NNLS started from each row's previous volumes).

    ``operators``: the stencils kept — "laplacian", "div-a-grad", "gradient", "dx"/"dy"/"dz", "hessian", and the
    vector operators "divergence", "curl", "grad-div-composed" (from the gradient), "grad-div" (from
    the Hessian) and "vector-laplacian" (from the Laplacian). ``h``/``h_factor``/``kernel``/``options`` as for :func:`stencil`; ``skin``: the
    Verlet skin as a fraction of the support radius; ``warm_start=False`` makes every update
    equal a fresh build bit for bit (with it VRSPH's rows meet the same moment conditions but may
    pick other volumes; ``share_volumes``, on by default with it, lets VRSPH's gradient rows take the
    Laplacian's volumes where these meet the Laplace conditions, which contain the gradient's,
    instead of solving their own: ``stats["borrowed_rows"]``). On a periodic cloud the rows that read only pair vectors (VRSPH's point
    rows, FPM with v = dx^d) take the minimum-image list; others are rebuilt on the images.

    ``coefficient`` (with "div-a-grad", required): a in div(a grad u), one value per particle
    (an array, a number, a callable of the coordinates or an expression in x, y, z, evaluated
    at the cloud's places); it moves with its particle. ``update(positions, coefficient=a)`` replaces it with the positions,
    ``set_coefficient(a)`` replaces it now (the stencil rebuilt on the current positions).

    ``update(positions)`` takes an (N, dim) array (the same particles; InputError otherwise, and
    the operators stay as they were). ``update(positions, neighbours=...)`` uses the caller's
    candidate pairs at the new positions instead of the operators' own Verlet list: ``(indptr,
    indices[, distances])`` or a SciPy sparse matrix's pattern, any superset of the pairs within
    the support radius (a cell list's or Verlet list's pairs); pairs beyond the radius are dropped,
    the rest checked as :func:`stencil` checks a list. ``stencil(op)`` returns what :func:`stencil` returns (a
    CSR matrix, or a tuple of them); ``apply(op, values)`` applies it to (N,) or (N, dim) values;
    ``stats`` reports the last update (searches, warm-start rows and hits, borrowed rows, seconds)."""

    def __init__(self, cloud: Cloud, method: str = "vrsph", operators: Sequence[str] = ("laplacian", "gradient"),
                 h: float | None = None, h_factor: float = 3.0, kernel: str = "cubic",
                 options: Mapping[str, Any] | None = None, skin: float = 0.2, warm_start: bool = True,
                 share_volumes: bool = True, coefficient: Data = None):
        _check_cloud(cloud)
        wanted = _args.names(operators, "operators")
        base: list[str] = []
        for name in wanted:
            b = _VECTOR_BASE.get(name, name)
            if b not in base:
                base.append(b)
        self._names = wanted
        self._ops = _vrsph._Operators(cloud, _args.text(method, "method"), base, _args.optional_length(h, "h"),
                                      _args.number(h_factor, "h_factor", positive=True), _args.text(kernel, "kernel"),
                                      _args.options(options, "options"), _args.number(skin, "skin", minimum=0.0),
                                      _args.flag(warm_start, "warm_start"), _args.flag(share_volumes, "share_volumes"),
                                      None if coefficient is None else _values(cloud, coefficient, "coefficient"))

    @staticmethod
    def _positions(positions: Any) -> np.ndarray:
        try:
            return np.asarray(positions, dtype=float)
        except (TypeError, ValueError) as e:
            raise ArgumentTypeError(f"the parameter positions must be an (N, dim) array of numbers: {e}") from None

    def _coefficient(self, a: Any) -> Any:
        if np.isscalar(a) and not isinstance(a, str):
            return np.full(self._ops.n, float(a))
        return a  # an array: the library checks dtype, shape and values

    def update(self, positions: Any, coefficient: Any = None, neighbours: Any = None) -> None:
        x = self._positions(positions)
        candidates = _args.neighbour_list(neighbours, "neighbours", self._ops.n)
        self._ops.update(x, None if coefficient is None else self._coefficient(coefficient), candidates)

    def set_coefficient(self, coefficient: Any) -> None:
        """div(a grad)'s a from now on (N positive values, a number, or an expression evaluated at
        the current positions): its stencil is rebuilt on them."""
        self._ops.set_coefficient(self._coefficient(coefficient))

    @property
    def coefficient(self) -> np.ndarray:
        return self._ops.coefficient

    def wrap(self, positions: Any) -> np.ndarray:
        """``positions`` (N, dim) moved into the cloud's periodic box along its periodic axes
        (lo + (x - lo) mod period; the other axes as given): ``update`` refuses a particle outside
        the box rather than wrapping it, so a time step that moves particles across a periodic
        face calls ``ops.update(ops.wrap(x))``."""
        return self._ops.wrap(self._positions(positions))

    @property
    def positions(self) -> np.ndarray:
        return self._ops.positions

    @property
    def radius(self) -> float:
        return self._ops.radius

    @property
    def support_radii(self) -> np.ndarray:
        """The support radius of each particle's rows (all ``radius`` unless set_support_radii)."""
        return self._ops.support_radii

    def set_support_radii(self, radii: Any) -> None:
        """Per-particle support radii from the next ``update`` on (N positive values; on a periodic
        box below half the shortest period less the skin): every row reads its own particle's
        radius (docs/moving.md)."""
        try:
            r = np.asarray(radii, dtype=float).reshape(-1)
        except (TypeError, ValueError) as e:
            raise ArgumentTypeError(f"the parameter radii must be an array of numbers: {e}") from None
        self._ops.set_support_radii(r.tolist())

    @property
    def stats(self) -> dict:
        return self._ops.stats()

    def support_isotropy(self) -> np.ndarray:
        """Per particle, the smallest over the largest eigenvalue of its neighbours' second moments
        about it (weights (1 - r/h)^2 inside the support): 1 on a lattice, towards 0 as the
        neighbours close onto a line (2D) or a plane (3D) and the rows lose the derivative across it
        (docs/flow.md, "Regularity over time")."""
        return self._ops.support_isotropy()

    def _matrices(self, name: str) -> tuple:
        raw = self._ops.stencil(name)
        n = self._ops.n
        return tuple(scipy.sparse.csr_matrix((d, raw["indices"], raw["indptr"]), shape=(n, n)) for d in raw["data"])

    def stencil(self, operator: str = "laplacian"):
        operator = _args.text(operator, "operator")
        base = _VECTOR_BASE.get(operator, operator)
        m = self._matrices(base)  # ConfigError when `base` is not kept
        if operator == "curl":
            if self._ops.dim == 1:
                raise ConfigError("the curl needs 2 or 3 dimensions, got 1")
            return (-m[1], m[0]) if self._ops.dim == 2 else m
        if operator == "grad-div":
            return _grad_div_from_hessian(m, self._ops.dim)
        return m if base in ("gradient", "hessian") else m[0]

    def apply(self, operator: str, values: Any) -> np.ndarray:
        operator = _args.text(operator, "operator")
        u = np.asarray(values, dtype=float)
        s = self.stencil(operator)
        dim, n = self._ops.dim, self._ops.n
        if operator in _VECTOR_BASE:
            if u.shape != (n, dim):
                raise InputError(f"{operator}: values of shape {u.shape} for an ({n}, {dim}) vector field")
            if operator == "grad-div":
                return np.column_stack([sum(s[b][c] @ u[:, c] for c in range(dim)) for b in range(dim)])
            if operator in ("divergence", "grad-div-composed"):
                d = sum(s[c] @ u[:, c] for c in range(dim))
                return d if operator == "divergence" else np.column_stack([g @ d for g in s])
            if operator == "vector-laplacian":
                return s @ u
            if dim == 2:
                return s[0] @ u[:, 0] + s[1] @ u[:, 1]
            g = s
            return np.column_stack([g[1] @ u[:, 2] - g[2] @ u[:, 1], g[2] @ u[:, 0] - g[0] @ u[:, 2],
                                    g[0] @ u[:, 1] - g[1] @ u[:, 0]])
        if u.shape != (n,):
            raise InputError(f"{operator}: values of shape {u.shape} for {n} particles")
        return np.column_stack([m @ u for m in s]) if isinstance(s, tuple) else s @ u


class Flow:
    """Incompressible flow on a cloud by Runge-Kutta with a pressure per stage and a projection
    per step (``vrsph flow``; docs/flow.md). The box is periodic along its periodic axes; the
    particles tagged dirichlet (with outward normals) are walls, at rest or moving along
    themselves with the rows of ``wall_velocity`` (an (N, dim) array; None: at rest).
    ``velocity``: the initial (N, dim) field (projected once). ``frame``: "eulerian" (the cloud
    stays) or "lagrangian" (particles move with the flow, walls stay; ``shifting`` "none", "xu"
    or "lind"). ``body_force``: g (dim values), reached over ``body_force_ramp``;
    ``free_surface``: p = 0 on the detected surface (docs/free_surface.md), ``free_surface``
    the property: the flags. ``viscosity``: "explicit" (in the Runge-Kutta rate, dt limited like
    dx²/nu) or "implicit" (IMEX stages, dt limited by the explicit terms only; docs/flow.md).
    ``support_growth`` (Lagrangian, > 1): every support grows by 15 % a step, up to this times
    h, while the least isotropic one is below ``support_isotropy``, and shrinks back once all are
    above twice it (docs/flow.md, "Regularity over time"); 1: fixed supports; 0 (the default): up
    to 9 spacings, capped below half the period, for a 2D Lagrangian flow on a periodic box without walls, free
    surface or shifting, 1 elsewhere. ``warm_start`` (VRSPH's volumes from each row's previous active
    set): None (the default) is off in that same case, where warm rows drift to less accurate ones
    over many steps, and on elsewhere. Free surfaces: ``wall_acceleration`` "momentum" or
    "body-force" (what the walls' extrapolated pressure carries), ``surface_gradient`` "linear" (the
    surface particles without a wall neighbour take the gradient's linear fit) or "same"; Lagrangian:
    ``wall_gap`` (spacings a particle is kept off a wall's face; 0: none) and ``shift_limit`` (the
    largest shift of a step, in spacings; 0: unbounded), as the CLI's options of those names;
    ``surface_film`` (``--surface-film``, 0.1): a water particle whose water neighbours alone are
    thin (a jet one particle thick up a wall) is surface (0: the scan alone decides).
    ``pressure_corrections``: defect corrections of every stage's pressure toward a divergence-free
    rate (``--pressure-corrections``; 0: none, as before 2026-12-06; None, the default: 1 with
    ``method="vrsph"``, 0 with the others; docs/flow.md).
    ``method`` builds the Laplacian (pressure Poisson, viscous term);
    ``gradient`` "auto" pairs VRSPH with FPM's second-order gradient. ``step(dt)`` returns the
    step's diagnostics; ``pressure()`` the pressure of the current velocity."""

    def __init__(self, cloud: Cloud, velocity: Any, frame: str = "eulerian", method: str = "vrsph", gradient: str = "auto",
                 nu: float = 0.01, scheme: str = "rk3", h_factor: float = 3.0, kernel: str = "cubic",
                 options: Mapping[str, Any] | None = None, shifting: str = "none", shift_coefficient: float = 0.0,
                 allow_unstable: bool = False, wall_velocity: Any = None, body_force: Any = None,
                 free_surface: bool = False, body_force_ramp: float = 0.0, viscosity: str = "explicit",
                 support_growth: float = 0.0, support_isotropy: float = 0.3, warm_start: bool | None = None,
                 wall_acceleration: str = "momentum", surface_gradient: str = "linear", wall_gap: float = 0.0,
                 shift_limit: float = 0.25, pressure_corrections: int | None = None, surface_film: float = 0.1):
        _check_cloud(cloud)
        self._s = _vrsph._FlowSolver(cloud, np.asarray(velocity, dtype=float), _args.text(frame, "frame"),
                                     _args.text(method, "method"), _args.text(gradient, "gradient"),
                                     _args.number(nu, "nu", minimum=0.0), _args.text(scheme, "scheme"),
                                     _args.number(h_factor, "h_factor", positive=True), _args.text(kernel, "kernel"),
                                     _args.options(options, "options"), _args.text(shifting, "shifting"),
                                     _args.number(shift_coefficient, "shift_coefficient", minimum=0.0),
                                     _args.flag(allow_unstable, "allow_unstable"),
                                     None if wall_velocity is None else np.asarray(wall_velocity, dtype=float),
                                     None if body_force is None else np.asarray(body_force, dtype=float).reshape(1, -1),
                                     _args.flag(free_surface, "free_surface"),
                                     _args.number(body_force_ramp, "body_force_ramp", minimum=0.0),
                                     _args.text(viscosity, "viscosity"),
                                     _args.number(support_growth, "support_growth", minimum=0.0),
                                     _args.number(support_isotropy, "support_isotropy", positive=True),
                                     None if warm_start is None else _args.flag(warm_start, "warm_start"),
                                     _args.text(wall_acceleration, "wall_acceleration"),
                                     _args.text(surface_gradient, "surface_gradient"),
                                     _args.number(wall_gap, "wall_gap", minimum=0.0),
                                     _args.number(shift_limit, "shift_limit", minimum=0.0),
                                     _args.pressure_corrections(pressure_corrections),
                                     _args.number(surface_film, "surface_film", minimum=0.0))

    def step(self, dt: float) -> dict:
        return self._s.step(_args.number(dt, "dt", positive=True))

    def stable_time_step(self, safety: float = 0.9) -> float:
        return self._s.stable_time_step(_args.number(safety, "safety", positive=True))

    def pressure(self) -> np.ndarray:
        return self._s.pressure()

    @property
    def velocity(self) -> np.ndarray:
        return self._s.velocity

    @property
    def positions(self) -> np.ndarray:
        return self._s.positions

    @property
    def time(self) -> float:
        return self._s.time

    @property
    def max_divergence(self) -> float:
        return self._s.max_divergence

    @property
    def free_surface(self) -> np.ndarray:
        return self._s.free_surface


def cavity(nx: int = 32, re: float = 100.0, method: str = "vrsph", gradient: str = "auto", jitter: float = 0.2,
           seed: int = 1, t_end: float = 100.0, steady_tol: float = 1e-4, cfl: float = 0.25, h_factor: float = 3.0,
           options: Mapping[str, Any] | None = None, viscosity: str = "explicit", frame: str = "eulerian",
           shifting: str = "none", wall_layers: int = 0, pressure_corrections: int | None = None) -> dict:
    """One row of ``vrsph flow --case cavity``: the lid-driven cavity (Re 100 or 1000) on the unit
    square with ``nx`` intervals per side, run until steady; the largest centre-line deviations
    from Ghia et al. (1982), the values at their points and the profiles on 101 points.
    ``frame="lagrangian"`` moves the particles (``shifting="xu"`` advised; three wall layers by
    default): its profiles are the mean of samples every 0.5 time units over the last 4.5, with
    ``profile_fluctuation`` their spread. ``pressure_corrections`` as for :class:`Flow`; the row
    says how many were used."""
    return _vrsph._cavity(_args.integer(nx, "nx", minimum=8), _args.number(re, "re", positive=True),
                          _args.text(method, "method"), _args.text(gradient, "gradient"),
                          _args.number(jitter, "jitter", minimum=0.0), _args.integer(seed, "seed", minimum=0),
                          _args.number(t_end, "t_end", positive=True),
                          _args.number(steady_tol, "steady_tol", positive=True), _args.number(cfl, "cfl", positive=True),
                          _args.number(h_factor, "h_factor", positive=True), _args.options(options, "options"),
                          _args.text(viscosity, "viscosity"), _args.text(frame, "frame"), _args.text(shifting, "shifting"),
                          _args.integer(wall_layers, "wall_layers", minimum=0),
                          _args.pressure_corrections(pressure_corrections))


def taylor_green(nx: int = 32, dim: int = 2, frame: str = "eulerian", method: str = "vrsph", gradient: str = "auto",
                 t_end: float = 1.0, re: float = 100.0, cfl: float = 0.25, jitter: float = 0.2, seed: int = 1,
                 scheme: str = "rk3", h_factor: float = 3.0, options: Mapping[str, Any] | None = None,
                 shifting: str = "none", shift_coefficient: float = 0.0, viscosity: str = "explicit",
                 support_growth: float = 0.0, support_isotropy: float = 0.3, warm_start: bool | None = None,
                 pressure_corrections: int | None = None) -> dict:
    """One row of ``vrsph flow --case taylor-green`` (2D Taylor-Green, 3D Beltrami vortex): the
    errors at ``t_end`` on the periodic unit box with ``nx`` particles per period. ``warm_start``
    as for :class:`Flow` (``--warm-start``): None picks per flow, the row's ``volumes`` says which;
    ``pressure_corrections`` likewise, the row's ``pressure_corrections`` the number used."""
    return _vrsph._taylor_green(_args.integer(nx, "nx", minimum=4), _args.integer(dim, "dim", minimum=2),
                                _args.text(frame, "frame"), _args.text(method, "method"), _args.text(gradient, "gradient"),
                                _args.number(t_end, "t_end", positive=True), _args.number(re, "re", positive=True),
                                _args.number(cfl, "cfl", positive=True), _args.number(jitter, "jitter", minimum=0.0),
                                _args.integer(seed, "seed", minimum=0), _args.text(scheme, "scheme"),
                                _args.number(h_factor, "h_factor", positive=True), _args.options(options, "options"),
                                _args.text(shifting, "shifting"),
                                _args.number(shift_coefficient, "shift_coefficient", minimum=0.0),
                                _args.text(viscosity, "viscosity"),
                                _args.number(support_growth, "support_growth", minimum=0.0),
                                _args.number(support_isotropy, "support_isotropy", positive=True),
                                None if warm_start is None else _args.flag(warm_start, "warm_start"),
                                _args.pressure_corrections(pressure_corrections))


def hydrostatic(nx: int = 20, dim: int = 2, frame: str = "lagrangian", method: str = "vrsph", jitter: float = 0.2,
                seed: int = 1, t_end: float = 2.0, gravity: float = 1.0, ramp: float = 0.5, h_factor: float = 3.0,
                options: Mapping[str, Any] | None = None, surface_gradient: str = "linear",
                wall_height: float = 0.0, surface_film: float = 0.1) -> dict:
    """One row of ``vrsph flow --case hydrostatic``: water of depth 1 at rest in a tank of width 1
    (``nx`` intervals across) under gravity ramped in over ``ramp``, run to ``t_end``: the bottom
    pressure against g H, the spurious speeds in (g H)^(1/2), the surface's particles.
    ``surface_gradient`` as ``--surface-gradient``: "linear" (the gradient rows of the surface
    particles without a wall neighbour a linear fit) or "same" (the flow's quadratic fit there
    too). ``wall_height``: the walls' height (``--wall-height``; 0: the
    water's depth, walls ending at its level). ``surface_film`` as for :class:`FlowSolver`."""
    return _vrsph._hydrostatic(_args.integer(nx, "nx", minimum=4), _args.integer(dim, "dim", minimum=2),
                               _args.text(frame, "frame"), _args.text(method, "method"),
                               _args.number(jitter, "jitter", minimum=0.0), _args.integer(seed, "seed", minimum=0),
                               _args.number(t_end, "t_end", positive=True), _args.number(gravity, "gravity"),
                               _args.number(ramp, "ramp", minimum=0.0), _args.number(h_factor, "h_factor", positive=True),
                               _args.options(options, "options"), _args.text(surface_gradient, "surface_gradient"),
                               _args.number(wall_height, "wall_height", minimum=0.0),
                               _args.number(surface_film, "surface_film", minimum=0.0))


def dam_break(nx: int = 20, method: str = "vrsph", jitter: float = 0.0, seed: int = 1, t_star_end: float = 3.0,
              shifting: str = "xu", cfl: float = 0.25, h_factor: float = 3.0,
              options: Mapping[str, Any] | None = None, geometry: str = "martin-moyce",
              wall_acceleration: str = "momentum", surface_gradient: str = "linear",
              surface_film: float = 0.1) -> dict:
    """``vrsph flow --case dam-break`` for one method and resolution. ``geometry="martin-moyce"``
    (``nx`` intervals across the column L x 2L, tank 4L): the surge front z/L and the column's
    height at samples of T = t (2g/L)^(1/2), beside Martin & Moyce's experiments (their spread)
    and Koshizuka & Oka's MPS. ``geometry="buchner"`` (column 2H x H, tank 5.366H, ``nx``
    intervals across H, T = t (g/H)^(1/2)): also ``probe_pressure`` p/(rho g H) on the far wall at
    probe P1 beside Buchner's record (``probe_reference``). The run goes on after the front
    reaches the far wall (``far_wall_t_star``); ``wall_acceleration="body-force"`` lets it run
    through the impact (docs/free_surface.md); ``surface_gradient`` and ``surface_film`` as for
    :func:`hydrostatic`;
    ``stopped`` says why a run ended early (its samples before are kept)."""
    return _vrsph._dam_break(_args.integer(nx, "nx", minimum=2), _args.text(method, "method"),
                             _args.number(jitter, "jitter", minimum=0.0), _args.integer(seed, "seed", minimum=0),
                             _args.number(t_star_end, "t_star_end", positive=True), _args.text(shifting, "shifting"),
                             _args.number(cfl, "cfl", positive=True), _args.number(h_factor, "h_factor", positive=True),
                             _args.options(options, "options"), _args.text(geometry, "geometry"),
                             _args.text(wall_acceleration, "wall_acceleration"),
                             _args.text(surface_gradient, "surface_gradient"),
                             _args.number(surface_film, "surface_film", minimum=0.0))


class Solution(dict):
    """The result of :func:`solve`: ``u`` and the diagnostics (``mmatrix``, ``infeasible``,
    ``solver``, ``solver_iterations``, ``solver_residual``, ``h``, ``warnings``, ...), and with
    an exact ``u`` given: ``exact``, ``error_inf``, ``error_l2``. Keys are also attributes."""

    def __getattr__(self, name: str):
        try:
            return self[name]
        except KeyError as e:
            raise AttributeError(name) from e


def _check_cloud(cloud: Any) -> None:
    if not isinstance(cloud, Cloud):
        raise ConfigError(f"the parameter cloud must be a vrsph.Cloud (vrsph.cloud.*, vrsph.read_cloud), got "
                          f"{type(cloud).__name__}")


def _coordinates(cloud: Cloud):
    p = cloud.points
    return tuple(p[:, k] for k in range(cloud.dim))


def _values(cloud: Cloud, data: Data, role: str):
    """Per-particle values of a datum given as a callable f(x[, y[, z]]) of coordinate arrays,
    a number or an array-like of N values (expressions are handled by the library)."""
    n = len(cloud)
    if callable(data):
        out = data(*_coordinates(cloud))
        arr = np.asarray(out, dtype=float)
        if arr.ndim == 0:
            arr = np.full(n, float(arr))
        if arr.shape != (n,):
            raise InputError(f"{role}: the callable returned shape {arr.shape}, expected ({n},)")
        return np.ascontiguousarray(arr)
    if np.isscalar(data) and not isinstance(data, str):
        return np.full(n, float(data))
    return data  # an array: the library checks dtype and shape


@dataclass
class Problem:
    """div(a grad u) = f on ``cloud``: u = g on Dirichlet particles, a du/dn = q on Neumann ones;
    ``u`` the exact solution if known. Each datum as :func:`solve` takes it."""
    cloud: Cloud
    f: Data = None
    g: Data = None
    q: Data = None
    a: Data = None
    u: Data = None


def solve(cloud: Cloud | Problem, f: Data = None, g: Data = None, q: Data = None, a: Data = None, u: Data = None,
          method: str = "vrsph", options: Mapping[str, Any] | None = None,
          h: float | None = None, h_factor: float = 3.0, h_mode: str = "fixed", kernel: str = "cubic", solver: str = "auto",
          petsc_options: str = "", fix_constant: bool = False, on_infeasible: str = "warn",
          infeasible_tol: float = 1e-6, mobility: Sequence[str] | None = None, robin: Data = None,
          return_system: bool = False, distributed: bool = False) -> Solution:
    """Solves div(a grad u) = f with u = g on Dirichlet particles and a du/dn = q on Neumann
    ones (outward normals from the cloud), one call into the library.

    Each datum is an expression string in x, y, z (as the CLI's), a number, an array of N
    values, or a callable of the coordinate arrays; ``u``, the exact solution, is optional:
    with it f, g and q default to what u implies and the errors are reported. A
    :class:`Problem` may stand for the cloud and the data: ``solve(Problem(cloud, f=..., g=...))``.
    ``mobility``: a diagonal tensor M = diag(m_1..m_d) as one expression per direction instead
    of ``a`` (vrsph and the [SPE] schemes brookshaw, cb-sph, s-sph, m-sph); f and q then default to
    div(M grad u) and n.M grad u.

    ``robin``: beta >= 0 per particle (a number, an array of N values or a callable): the Neumann
    particles then carry a du/dn + beta u = q (with ``u`` given and no ``q``, q includes beta u).
    ``return_system=True`` adds ``system`` (the assembled ``matrix`` A as scipy CSR over the
    unknowns, ``rhs`` b and ``dofs``: the particle of each unknown) and ``operator_rows`` (the
    div(a grad) rows over every particle); balance rows give ``wall_flux`` (c_i per particle).

    ``distributed=True``: run under ``mpirun -np P python3 ...``, every rank passing its own
    part of the cloud (e.g. ``cloud.perturbed(..., distributed=True)``; the parts in rank order
    are the whole cloud) and its data; the solve runs over the ranks as ``vrsph solve`` does
    under mpirun (PETSc; h-mode fixed), u comes back for this rank's particles and the errors
    are those of the whole cloud."""
    if isinstance(cloud, Problem):
        if any(d is not None for d in (f, g, q, a, u)):
            raise ConfigError("give the data in the Problem or as arguments, not both")
        cloud, f, g, q, a, u = cloud.cloud, cloud.f, cloud.g, cloud.q, cloud.a, cloud.u
    expressions, values = {}, {}
    for role, data in (("u", u), ("a", a), ("f", f), ("g", g), ("q", q)):
        if data is None:
            continue
        if isinstance(data, str):
            expressions[role] = data
        elif isinstance(data, (int, float, np.number)) and not isinstance(data, bool):
            expressions[role] = _args.expression(data, role)  # a constant: f, q still derive from it
        else:
            values[role] = _values(cloud, data, role)
    if mobility is not None:
        expressions["mobility"] = _args.expressions(mobility, "mobility")
    if robin is not None:
        values["robin"] = _values(cloud, robin, "robin")
    opts = dict(method=_args.text(method, "method"), method_options=_args.options(options, "options"),
                kernel=_args.text(kernel, "kernel"), h=_args.optional_length(h, "h"),
                h_factor=_args.number(h_factor, "h_factor", positive=True), h_mode=_args.text(h_mode, "h_mode"),
                solver=_args.text(solver, "solver"), petsc_options=_args.text(petsc_options, "petsc_options"),
                fix_constant=_args.flag(fix_constant, "fix_constant"),
                on_infeasible=_args.text(on_infeasible, "on_infeasible"),
                infeasible_tol=_args.number(infeasible_tol, "infeasible_tol", positive=True),
                return_system=_args.flag(return_system, "return_system"),
                distributed=_args.flag(distributed, "distributed"))
    out = Solution(_vrsph._solve(cloud, expressions, values, opts))
    for key in ("system", "operator_rows"):
        if key in out:
            raw = out[key]
            m = scipy.sparse.csr_matrix((raw["data"], raw["indices"], raw["indptr"]), shape=tuple(raw["shape"]))
            out[key] = m if key == "operator_rows" else {"matrix": m, "rhs": raw["rhs"], "dofs": np.asarray(raw["dofs"])}
    return out


def study(problem: str | None = None, methods: Sequence[str] = ("vrsph",), cloud: str = "uniform",
          n: Sequence[int] = (20, 40, 80, 160), seeds: Sequence[int] = (1,), dim: int | None = None,
          method_options: Mapping[str, Mapping[str, Any]] | None = None, h_factor: float | None = None,
          h_mode: str = "fixed", delta: float | None = None, kernel: str | None = None,
          neumann: Sequence[str] | None = None, u: str | None = None, a: str | None = None, f: str | None = None,
          g: str | None = None, q: str | None = None, fix_constant: bool = False, solver: str = "auto",
          petsc_options: str = "", perturb_boundary: bool = False, regular_layer: float = 0.0,
          mobility: Sequence[str] | None = None, layout: str | None = None,
          on_infeasible: str = "warn", infeasible_tol: float = 1e-6, robin: Sequence[str] | None = None,
          beta: str | None = None) -> list[dict]:
    """A convergence study as ``vrsph study`` runs it (same defaults, same numbers): one row
    per (method, n) with the fields of the CLI's JSON (``error_inf``, ``order_inf``,
    ``mmatrix``, ``solver_iterations``, ...), the mean over ``seeds`` for random clouds.

    The study's metadata (fitted orders, warnings) is in ``vrsph.study_report(...)``."""
    return study_report(**{k: v for k, v in locals().items()})["rows"]


def study_report(problem: str | None = None, methods: Sequence[str] = ("vrsph",), cloud: str = "uniform",
                 n: Sequence[int] = (20, 40, 80, 160), seeds: Sequence[int] = (1,), dim: int | None = None,
                 method_options: Mapping[str, Mapping[str, Any]] | None = None, h_factor: float | None = None,
                 h_mode: str = "fixed", delta: float | None = None, kernel: str | None = None,
                 neumann: Sequence[str] | None = None, u: str | None = None, a: str | None = None,
                 f: str | None = None, g: str | None = None, q: str | None = None, fix_constant: bool = False,
                 solver: str = "auto", petsc_options: str = "", perturb_boundary: bool = False,
                 regular_layer: float = 0.0, mobility: Sequence[str] | None = None, layout: str | None = None,
                 on_infeasible: str = "warn", infeasible_tol: float = 1e-6, robin: Sequence[str] | None = None,
                 beta: str | None = None) -> dict:
    """:func:`study` with the metadata: ``{"rows": [...], "fitted_order_inf": {...}, "warnings": [...], ...}``."""
    params = _checked_study_params(dict(locals()))
    params["seeds"] = _args.integers(seeds, "seeds", minimum=0)
    params["fix_constant"] = _args.flag(fix_constant, "fix_constant")
    params["perturb_boundary"] = _args.flag(perturb_boundary, "perturb_boundary")
    params["infeasible_tol"] = _args.number(infeasible_tol, "infeasible_tol", positive=True)
    for key in ("solver", "petsc_options", "on_infeasible"):
        params[key] = _args.text(params[key], key)
    for key in ("neumann", "robin"):
        params[key] = _args.expressions(params[key], key)
    params["beta"] = _args.expression(beta, "beta")
    return _vrsph._study(params)


def _checked_study_params(params: dict) -> dict:
    """The parameters study() and operator_study() share, checked and converted."""
    params["methods"] = _args.names(params["methods"], "methods")
    params["n"] = _args.integers(params["n"], "n", minimum=1)
    params["method_options"] = _args.per_method_options(params["method_options"], "method_options")
    params["cloud"] = _args.text(params["cloud"], "cloud")
    params["h_mode"] = _args.text(params["h_mode"], "h_mode")
    for key in ("problem", "kernel", "layout"):
        if key in params:
            params[key] = _args.optional_text(params[key], key)
    if params.get("dim") is not None:
        params["dim"] = _args.integer(params["dim"], "dim", minimum=1)
    for key in ("h_factor", "delta"):
        if params.get(key) is not None:
            params[key] = _args.number(params[key], key, positive=key == "h_factor", minimum=0.0)
    params["regular_layer"] = _args.number(params["regular_layer"], "regular_layer", minimum=0.0)
    for key in ("u", "a", "f", "g", "q", "exact"):
        if key in params:
            params[key] = _args.expression(params[key], key)
    if params.get("mobility") is not None:
        params["mobility"] = _args.expressions(params["mobility"], "mobility")
    return params


def operator_study(problem: str = "qw-trunc", methods: Sequence[str] = ("sph",), operator: str = "laplacian",
                   cloud: str = "uniform", n: Sequence[int] = (8, 16, 32, 64, 128), seed: int = 1,
                   dim: int | None = None, method_options: Mapping[str, Mapping[str, Any]] | None = None,
                   h_factor: float | None = None, h_mode: str = "fixed", delta: float | None = None,
                   ghosts: bool | None = None, regular_layer: float = 0.0, kernel: str | None = None,
                   u: str | None = None, exact: str | None = None, a: str | None = None) -> dict:
    """An operator (truncation-error) study as ``vrsph operator`` runs it: ``{"rows": [...],
    "fitted_order_inf": {...}, ...}`` with the fields of the CLI's JSON."""
    params = _checked_study_params(dict(locals()))
    params["operator"] = _args.text(operator, "operator")
    params["seed"] = _args.integer(seed, "seed", minimum=0)
    if ghosts is not None:
        params["ghosts"] = _args.flag(ghosts, "ghosts")
    return _vrsph._operator_study(params)
