# SPDX-License-Identifier: BSD-3-Clause
"""An independent reference for the lid-driven cavity (docs/flow.md): the steady Navier-Stokes
equations with Taylor-Hood P2-P1 finite elements (FEniCSx/dolfinx 0.5 from Debian, Newton with a
direct solve, Re reached by continuation 100 -> 400 -> 1000), the lid (1, 0) on y = 1 between the
corners and every other wall at rest, as vrsph's cavity. Prints, for each Re asked and each n,
u(0.5, y) and v(x, 0.5) at Ghia et al.'s points and their largest deviation from Ghia's table, as
JSON lines. Not part of the build or the tests: it measures the table's own error.

    apt-get install -y --no-install-recommends python3-dolfinx-real python3-petsc4py python3-mpi4py
    /usr/bin/python3 scripts/cavity_reference.py 64 128 --re 100 1000
"""
import argparse
import json
import time

import numpy as np
import ufl
from dolfinx import fem, geometry, mesh
from dolfinx.fem.petsc import NonlinearProblem
from dolfinx.nls.petsc import NewtonSolver
from mpi4py import MPI
from petsc4py import PETSc

GHIA_Y = [1.0000, 0.9766, 0.9688, 0.9609, 0.9531, 0.8516, 0.7344, 0.6172, 0.5000, 0.4531, 0.2813, 0.1719, 0.1016,
          0.0703, 0.0625, 0.0547, 0.0000]
GHIA_X = [1.0000, 0.9688, 0.9609, 0.9531, 0.9453, 0.9063, 0.8594, 0.8047, 0.5000, 0.2344, 0.2266, 0.1563, 0.0938,
          0.0781, 0.0703, 0.0625, 0.0000]
GHIA = {
    100: ([1.00000, 0.84123, 0.78871, 0.73722, 0.68717, 0.23151, 0.00332, -0.13641, -0.20581, -0.21090, -0.15662,
           -0.10150, -0.06434, -0.04775, -0.04192, -0.03717, 0.00000],
          [0.00000, -0.05906, -0.07391, -0.08864, -0.10313, -0.16914, -0.22445, -0.24533, 0.05454, 0.17527, 0.17507,
           0.16077, 0.12317, 0.10890, 0.10091, 0.09233, 0.00000]),
    1000: ([1.00000, 0.65928, 0.57492, 0.51117, 0.46604, 0.33304, 0.18719, 0.05702, -0.06080, -0.10648, -0.27805,
            -0.38289, -0.29730, -0.22220, -0.20196, -0.18109, 0.00000],
           [0.00000, -0.21388, -0.27669, -0.33714, -0.39188, -0.51550, -0.42665, -0.31966, 0.02526, 0.32235, 0.33075,
            0.37095, 0.32627, 0.30353, 0.29012, 0.27485, 0.00000]),
}


def evaluate(msh, f, points):
    """f at the points (3 x m array), serial."""
    tree = geometry.BoundingBoxTree(msh, msh.topology.dim)
    candidates = geometry.compute_collisions(tree, points.T)
    colliding = geometry.compute_colliding_cells(msh, candidates, points.T)
    cells = [colliding.links(i)[0] for i in range(points.shape[1])]
    return f.eval(points.T, np.array(cells, dtype=np.int32))


def solve(n, res):
    msh = mesh.create_unit_square(MPI.COMM_WORLD, n, n, mesh.CellType.triangle, diagonal=mesh.DiagonalType.crossed)
    P2 = ufl.VectorElement("Lagrange", msh.ufl_cell(), 2)
    P1 = ufl.FiniteElement("Lagrange", msh.ufl_cell(), 1)
    W = fem.FunctionSpace(msh, ufl.MixedElement([P2, P1]))
    V, _ = W.sub(0).collapse()
    Q, _ = W.sub(1).collapse()
    lid, rest = fem.Function(V), fem.Function(V)
    lid.interpolate(lambda x: np.vstack([np.where((x[0] > 1e-12) & (x[0] < 1 - 1e-12), 1.0, 0.0), 0 * x[0]]))
    fdim = msh.topology.dim - 1
    top = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[1], 1.0))
    others = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[0], 0) | np.isclose(x[0], 1) | np.isclose(x[1], 0))
    bcs = [fem.dirichletbc(lid, fem.locate_dofs_topological((W.sub(0), V), fdim, top), W.sub(0)),
           fem.dirichletbc(rest, fem.locate_dofs_topological((W.sub(0), V), fdim, others), W.sub(0))]  # corners at rest
    corner = fem.locate_dofs_geometrical((W.sub(1), Q), lambda x: np.isclose(x[0], 0) & np.isclose(x[1], 0))
    zero = fem.Function(Q)
    bcs.append(fem.dirichletbc(zero, corner, W.sub(1)))
    w = fem.Function(W)
    u, p = ufl.split(w)
    v, q = ufl.TestFunctions(W)
    nu = fem.Constant(msh, PETSc.ScalarType(1.0 / res[0]))
    F = (nu * ufl.inner(ufl.grad(u), ufl.grad(v)) + ufl.inner(ufl.grad(u) * u, v) - p * ufl.div(v) - q * ufl.div(u)) * ufl.dx
    problem = NonlinearProblem(F, w, bcs=bcs)
    newton = NewtonSolver(MPI.COMM_WORLD, problem)
    newton.rtol = 1e-12
    newton.atol = 1e-12
    newton.max_it = 30
    ksp = newton.krylov_solver
    opts = PETSc.Options()
    prefix = ksp.getOptionsPrefix()
    opts[f"{prefix}ksp_type"] = "preonly"
    opts[f"{prefix}pc_type"] = "lu"
    opts[f"{prefix}pc_factor_mat_solver_type"] = "mumps"
    ksp.setFromOptions()
    out = []
    for re in res:  # continuation: each Re starts from the last one's solution
        nu.value = 1.0 / re
        start = time.perf_counter()
        iterations, converged = newton.solve(w)
        seconds = time.perf_counter() - start
        if re not in GHIA:
            continue
        uh = w.sub(0).collapse()
        pu = np.array([[0.5, y, 0.0] for y in GHIA_Y]).T
        pv = np.array([[x, 0.5, 0.0] for x in GHIA_X]).T
        u_at = evaluate(msh, uh, pu)[:, 0]
        v_at = evaluate(msh, uh, pv)[:, 1]
        gu, gv = GHIA[re]
        inside = slice(1, len(GHIA_Y) - 1)
        out.append({"re": re, "n": n, "dofs": W.dofmap.index_map.size_global * W.dofmap.index_map_bs,
                    "newton_iterations": iterations, "converged": bool(converged), "seconds": seconds,
                    "ghia_max_deviation_u": float(np.max(np.abs(u_at - gu)[inside])),
                    "ghia_max_deviation_v": float(np.max(np.abs(v_at - gv)[inside])),
                    "u_at_ghia": [float(a) for a in u_at], "v_at_ghia": [float(a) for a in v_at]})
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("n", type=int, nargs="+", help="cells per side (crossed triangles)")
    parser.add_argument("--re", type=int, nargs="+", default=[100, 1000], choices=[100, 1000])
    a = parser.parse_args()
    path = [100] + ([400, 1000] if 1000 in a.re else [])
    for n in a.n:
        for row in solve(n, path):
            if row["re"] in a.re:
                print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
