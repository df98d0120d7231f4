// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The approximate projection of ISPH/MPS, with one method's operators on the particles: a
// velocity w (N x d) is made discretely divergence-free by
//     L φ = D w,    u = w - G φ
// with the method's Laplacian L (its pressure Poisson rows), gradient G and divergence D = Σ_c G_c.
// "Approximate": L is the method's own Laplacian, not D G, so D u is not zero but the Laplacian's
// truncation error applied to φ (second order for VRSPH); on a periodic box the part of D w no
// gradient can remove (its mean, in the left null vector's weights) is returned as the shift.
#include <vrsph/flow/pressure_poisson.hpp>
#include <vrsph/moving/operators.hpp>

namespace vrsph {

/// The operators' Laplacian as a matrix (a copy): what PressurePoisson factorises.
/// ConfigError when they keep no Laplacian or it has right-hand-side weights (compact rows: a
/// projection needs the operator's value at each particle).
CsrMatrix laplacian_matrix(const Operators& ops);

struct Projected {
  Eigen::MatrixXd u;  ///< w - G φ
  Field phi;          ///< the potential removed (zero mean)
  Real shift = 0;     ///< PressurePoisson::Result::shift
  SolveReport report;
};

/// w projected with the operators' L (factorised in `ppe`), G and D. `phi_guess`: an initial
/// guess for an iterative solver (empty: none). InputError for a w of another shape.
Projected project(const Operators& ops, const PressurePoisson& ppe, const Eigen::MatrixXd& w, const Field& phi_guess = {});

/// (u · G) u: the advection of u (N x d) by itself with the operators' gradient, N x d.
Eigen::MatrixXd advection(const Operators& ops, const Eigen::MatrixXd& u);

}  // namespace vrsph
