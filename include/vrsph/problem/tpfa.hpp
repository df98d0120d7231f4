// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Two-point flux approximation (TPFA): the cell-centred finite-volume reference of [SPE]
// §3 (66)-(67) and §5.3, on the Cartesian grid of a PermeabilityField.
//
// -div(K grad u) = 0 on [0,1]^d, u = p_in on the face x_axis = 0, u = p_out on x_axis = 1,
// no flow through the other faces. Interior faces carry the harmonic transmissibility
// T = A / (h/(2 k_I) + h/(2 k_J)) of the face-normal permeabilities; a Dirichlet face
// T = A k_I / (h/2). The rows are divided by the cell volume, so the system is a
// discretisation of div(K grad u) on the same scale as the particle operators (negative
// diagonal, non-negative off-diagonals: an M-matrix, monotone for any K). Exact for 1D
// layered media (layers across or along the flow).
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/problem/permeability.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

struct TpfaOptions {
  int flow_axis = 1;     ///< the pressure drop is along this axis (0: x, 1: y, 2: z)
  Real p_in = 1;         ///< u on the face x_axis = 0
  Real p_out = 0;        ///< u on the face x_axis = 1
  SolverOptions solver;
};

/// The TPFA system over the cells (dof c = cell c). Throws InputError (invalid field) and
/// ConfigError (axis outside the field's dimension, non-finite pressures).
LinearSystem assemble_tpfa(const PermeabilityField& field, const TpfaOptions& options = {});

struct TpfaSolution {
  Field pressure;          ///< per cell
  Real inlet_flux = 0;     ///< volumetric rate entering through x_axis = 0 (per unit depth in 2D)
  Real outlet_flux = 0;    ///< rate leaving through x_axis = 1
  SolveReport solve;
};

/// Assembles and solves; NumericalError when the solver fails.
TpfaSolution solve_tpfa(const PermeabilityField& field, const TpfaOptions& options = {});

/// The rate through the face x_axis = 0 (inlet) or 1 (outlet) of a cell pressure field,
/// from the Dirichlet half-cell transmissibilities.
Real tpfa_boundary_flux(const PermeabilityField& field, const Field& pressure, const TpfaOptions& options, bool outlet);

}  // namespace vrsph
