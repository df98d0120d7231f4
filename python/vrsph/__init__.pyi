# SPDX-License-Identifier: BSD-3-Clause
from typing import Any, Callable, Literal, Mapping, Sequence, Union, overload

import numpy as np
import numpy.typing as npt
import scipy.sparse

from . import cloud as cloud

INTERIOR: int
DIRICHLET: int
NEUMANN: int
GHOST: int

class Error(Exception): ...
__version__: str

class InputError(Error, ValueError): ...
class IoError(InputError, OSError): ...
class ConfigError(Error, ValueError): ...
class ResourceError(ConfigError, MemoryError): ...
class FeatureUnavailable(ConfigError): ...
class GeometryError(Error, ValueError): ...
class NumericalError(Error, RuntimeError): ...
class ArgumentTypeError(Error, TypeError): ...

# A caller's neighbour list: (indptr, indices), (indptr, indices, distances) or a sparse matrix's pattern.
NeighbourData = Union[tuple[npt.ArrayLike, npt.ArrayLike], tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike | None],
                      scipy.sparse.spmatrix, None]

class Cloud:
    dim: int
    fields: dict[str, npt.NDArray[np.float64]]
    @property
    def spacing(self) -> float: ...
    @property
    def periodic(self) -> str: ...
    @property
    def box(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None: ...
    @property
    def points(self) -> npt.NDArray[np.float64]: ...
    @property
    def normals(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def tags(self) -> npt.NDArray[np.uint8]: ...
    def count(self, tag: int) -> int: ...
    def __len__(self) -> int: ...

Data = Union[None, str, float, Sequence[float], npt.NDArray[Any], Callable[..., Any]]

def read_cloud(path: str, dim: int = 0, periodic: str = "", box=None) -> Cloud: ...
def parts() -> list[dict[str, Any]]: ...
def methods() -> list[dict[str, Any]]: ...
def kernels() -> list[dict[str, Any]]: ...
def covering_radius(cloud: Cloud) -> dict[str, Any]: ...
def free_surface(cloud: Cloud, *, criterion: Literal["eigenvalue", "number-density"] = "eigenvalue", h_factor: float = 2.5,
                 spacing: float = 0.0, density_threshold: float = 0.97, surface_eigenvalue: float = 0.2,
                 interior_eigenvalue: float = 0.75, scan: bool = True, only_interior: bool = False,
                 scan_every_neighbour: bool = False) -> dict[str, Any]: ...
def write_vtu(path: str, cloud: Cloud, fields: Mapping[str, npt.ArrayLike] = ..., ascii: bool = False) -> None: ...

class Stencil:
    matrices: tuple[scipy.sparse.csr_matrix, ...]
    residual: npt.NDArray[np.float64] | None
    condition: npt.NDArray[np.float64] | None
    infeasible: npt.NDArray[np.int32]
    rhs: scipy.sparse.csr_matrix | None
    h: float
    spacing: float
    row_forms: str
    @property
    def matrix(self) -> scipy.sparse.csr_matrix: ...

@overload
class Operators:
    def __init__(self, cloud: Cloud, method: str = ..., operators: Sequence[str] = ..., h: float | None = ...,
                 h_factor: float = ..., kernel: str = ..., options: Mapping[str, Any] | None = ..., skin: float = ...,
                 warm_start: bool = ..., share_volumes: bool = ..., coefficient: Any = ...) -> None: ...
    def update(self, positions: Any, coefficient: Any = ..., neighbours: Any = ...) -> None: ...
    def wrap(self, positions: Any) -> np.ndarray: ...
    def set_coefficient(self, coefficient: Any) -> None: ...
    @property
    def coefficient(self) -> np.ndarray: ...
    def set_support_radii(self, radii: Any) -> None: ...
    @property
    def support_radii(self) -> np.ndarray: ...
    @property
    def positions(self) -> np.ndarray: ...
    @property
    def radius(self) -> float: ...
    @property
    def stats(self) -> dict: ...
    def support_isotropy(self) -> np.ndarray: ...
    def stencil(self, operator: str = ...) -> Any: ...
    def apply(self, operator: str, values: Any) -> np.ndarray: ...

class Flow:
    def __init__(self, cloud: Cloud, velocity: Any, frame: str = ..., method: str = ..., gradient: str = ...,
                 nu: float = ..., scheme: str = ..., h_factor: float = ..., kernel: str = ...,
                 options: Mapping[str, Any] | None = ..., shifting: str = ..., shift_coefficient: float = ...,
                 allow_unstable: bool = ..., wall_velocity: Any = ..., body_force: Any = ...,
                 free_surface: bool = ..., body_force_ramp: float = ..., viscosity: str = ...,
                 support_growth: float = ..., support_isotropy: float = ..., warm_start: bool | None = ...,
                 wall_acceleration: str = ..., surface_gradient: str = ..., wall_gap: float = ...,
                 shift_limit: float = ..., pressure_corrections: int | None = ...) -> None: ...
    def step(self, dt: float) -> dict: ...
    def stable_time_step(self, safety: float = ...) -> float: ...
    def pressure(self) -> np.ndarray: ...
    @property
    def velocity(self) -> np.ndarray: ...
    @property
    def positions(self) -> np.ndarray: ...
    @property
    def time(self) -> float: ...
    @property
    def max_divergence(self) -> float: ...
    @property
    def free_surface(self) -> np.ndarray: ...

def cavity(nx: int = ..., re: float = ..., method: str = ..., gradient: str = ..., jitter: float = ...,
           seed: int = ..., t_end: float = ..., steady_tol: float = ..., cfl: float = ..., h_factor: float = ...,
           options: Mapping[str, Any] | None = ..., viscosity: str = ..., frame: str = ...,
           shifting: str = ..., wall_layers: int = ..., pressure_corrections: int | None = ...) -> dict: ...

def hydrostatic(nx: int = ..., dim: int = ..., frame: str = ..., method: str = ..., jitter: float = ...,
                seed: int = ..., t_end: float = ..., gravity: float = ..., ramp: float = ..., h_factor: float = ...,
                options: Mapping[str, Any] | None = ...) -> dict: ...

def dam_break(nx: int = ..., method: str = ..., jitter: float = ..., seed: int = ..., t_star_end: float = ...,
              shifting: str = ..., cfl: float = ..., h_factor: float = ...,
              options: Mapping[str, Any] | None = ...) -> dict: ...

def taylor_green(nx: int = ..., dim: int = ..., frame: str = ..., method: str = ..., gradient: str = ...,
                 t_end: float = ..., re: float = ..., cfl: float = ..., jitter: float = ..., seed: int = ...,
                 scheme: str = ..., h_factor: float = ..., options: Mapping[str, Any] | None = ...,
                 shifting: str = ..., shift_coefficient: float = ..., viscosity: str = ...,
                 support_growth: float = ..., support_isotropy: float = ..., warm_start: bool | None = ...,
                 pressure_corrections: int | None = ...) -> dict: ...

def stencil(cloud: Cloud, method: str = "vrsph", operator: str = "laplacian", h: float | None = None,
            h_factor: float = 3.0, kernel: str = "cubic", options: Mapping[str, Any] | None = None,
            coefficient: Data = None, infeasible_tol: float = 1e-6, *,
            diagnostics: Literal[True], neighbours: NeighbourData = None) -> Stencil: ...
@overload
def stencil(cloud: Cloud, method: str = "vrsph", operator: str = "laplacian", h: float | None = None,
            h_factor: float = 3.0, kernel: str = "cubic", options: Mapping[str, Any] | None = None,
            coefficient: Data = None, infeasible_tol: float = 1e-6,
            diagnostics: Literal[False] = False,
            neighbours: NeighbourData = None) -> scipy.sparse.csr_matrix | tuple[scipy.sparse.csr_matrix, ...]: ...

class Solution(dict[str, Any]):
    u: npt.NDArray[np.float64]
    mmatrix: bool
    infeasible: int
    solver: str
    solver_iterations: int
    solver_residual: float
    h: float
    warnings: list[str]
    infeasible_particles: list[int]
    infeasible_residuals: list[float]
    wall_flux: npt.NDArray[np.float64]  # balance rows only
    system: dict[str, Any]  # return_system=True: matrix (csr), rhs, dofs
    operator_rows: scipy.sparse.csr_matrix  # return_system=True
    def __getattr__(self, name: str) -> Any: ...

class Problem:
    cloud: Cloud
    f: Data
    g: Data
    q: Data
    a: Data
    u: Data
    def __init__(self, cloud: Cloud, f: Data = None, g: Data = None, q: Data = None, a: Data = None,
                 u: Data = None) -> None: ...

def solve(cloud: Cloud | Problem, f: Data = None, g: Data = None, q: Data = None, a: Data = None, u: Data = None,
          method: str = "vrsph", options: Mapping[str, Any] | None = None, h: float | None = None,
          h_factor: float = 3.0, h_mode: str = "fixed", kernel: str = "cubic", solver: str = "auto",
          petsc_options: str = "", fix_constant: bool = False, on_infeasible: str = "warn",
          infeasible_tol: float = 1e-6, mobility: Sequence[str] | None = None, robin: Data = None,
          return_system: bool = False, distributed: bool = False) -> Solution: ...

def study(problem: str | None = None, methods: Sequence[str] = ..., cloud: str = "uniform", n: Sequence[int] = ...,
          seeds: Sequence[int] = ..., dim: int | None = None, method_options: Mapping[str, Mapping[str, Any]] | None = None,
          h_factor: float | None = None, h_mode: str = "fixed", delta: float | None = None, kernel: str | None = None,
          neumann: Sequence[str] | None = None, u: str | None = None, a: str | None = None, f: str | None = None,
          g: str | None = None, q: str | None = None, fix_constant: bool = False, solver: str = "auto",
          petsc_options: str = "", perturb_boundary: bool = False, regular_layer: float = 0.0,
          mobility: Sequence[str] | None = None, layout: str | None = None,
          on_infeasible: str = "warn", infeasible_tol: float = 1e-6, robin: Sequence[str] | None = None,
          beta: str | None = None) -> list[dict[str, Any]]: ...
def study_report(**kwargs: Any) -> dict[str, Any]: ...
def operator_study(problem: str = "qw-trunc", methods: Sequence[str] = ..., operator: str = "laplacian",
                   cloud: str = "uniform", n: Sequence[int] = ..., seed: int = 1, dim: int | None = None,
                   method_options: Mapping[str, Mapping[str, Any]] | None = None, h_factor: float | None = None,
                   h_mode: str = "fixed", delta: float | None = None, ghosts: bool | None = None,
                   regular_layer: float = 0.0, kernel: str | None = None, u: str | None = None,
                   exact: str | None = None, a: str | None = None) -> dict[str, Any]: ...
