#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The Python module under mpirun: each rank solves its part of a perturbed cloud with
solve(..., distributed=True); the parts' u equal the serial solve of the whole cloud (which
every rank also computes) to the direct solvers' round-off, and the errors are the whole
cloud's. Usage: mpirun -np P python3 test_mpi_python.py (PYTHONPATH: the built module)."""
import sys

import numpy as np

import vrsph

DIRECT = "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps"
U = "exp(x)*sin(2*y) + x*y"


def main():
    whole = vrsph.cloud.perturbed(dim=2, n=24, seed=3)
    serial = vrsph.solve(whole, u=U, a="1 + x*y", solver="umfpack")
    part = vrsph.cloud.perturbed(dim=2, n=24, seed=3, distributed=True)
    par = vrsph.solve(part, u=U, a="1 + x*y", solver="petsc", petsc_options=DIRECT, distributed=True)
    mine = np.asarray(part.points)
    # The part's particles are a consecutive slice of the whole cloud: find where it starts.
    everything = np.asarray(whole.points)
    first = int(np.flatnonzero(np.all(np.isclose(everything, mine[0], rtol=0, atol=0), axis=1))[0]) if len(mine) else 0
    assert np.array_equal(everything[first:first + len(mine)], mine), "the part is not a slice of the whole cloud"
    scale = np.max(np.abs(serial.u))
    diff = np.max(np.abs(par.u - serial.u[first:first + len(mine)])) if len(mine) else 0.0
    assert diff <= 1e-10 * scale, f"u differs from serial by {diff}"
    assert abs(par.error_inf - serial.error_inf) <= 1e-10 * scale, (par.error_inf, serial.error_inf)  # as u
    assert par.particles == serial.particles and par.unknowns == serial.unknowns
    # Bad input is the same typed exception on every rank.
    try:
        vrsph.solve(part, u=U, solver="umfpack", distributed=True)
    except vrsph.ConfigError:
        pass
    else:
        raise AssertionError("a serial solver under MPI was not refused")
    print(f"rank ok: {len(mine)} particles, |u - u_serial| = {diff:.2e}, error_inf {par.error_inf:.6e}")


def periodic():
    # A fully periodic box over the ranks: the images are halo entries, u has zero mean.
    u = "sin(2*pi*x)*cos(2*pi*y)"
    whole = vrsph.cloud.perturbed(dim=2, n=20, seed=5, periodic="x,y")
    serial = vrsph.solve(whole, u=u, solver="umfpack")
    part = vrsph.cloud.perturbed(dim=2, n=20, seed=5, periodic="x,y", distributed=True)
    par = vrsph.solve(part, u=u, solver="petsc", petsc_options=DIRECT, distributed=True)
    assert par.particles == serial.particles
    assert abs(par.error_inf - serial.error_inf) <= 1e-9 * serial.error_inf, (par.error_inf, serial.error_inf)
    print(f"rank ok: periodic box, error_inf {par.error_inf:.6e} (serial {serial.error_inf:.6e})")


if __name__ == "__main__":
    main()
    periodic()
    sys.exit(0)
