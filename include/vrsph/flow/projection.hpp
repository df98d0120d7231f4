// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The approximate projection of ISPH/MPS, with one method's operators on the particles: a
// velocity w (N x d) is made discretely divergence-free by
//     L φ = D w,    u = w - G φ
// with the method's Laplacian L (its pressure Poisson rows), gradient G and divergence D = Σ_c G_c.
// "Approximate": L is the method's own Laplacian, not D G, so D u is not zero but the Laplacian's
// truncation error applied to φ (second order for VRSPH); on a periodic box the part of D w no
// gradient can remove (its mean, in the left null vector's weights) is returned as the shift.
//
// Walls (particles tagged Dirichlet: their velocity is prescribed) keep their velocity; their
// pressure rows are the Neumann rows n·G φ = n·(w - u_wall) = 0, so the projected velocity keeps
// the wall's normal velocity (the discrete form of the projection's boundary condition).
#include <vrsph/flow/pressure_poisson.hpp>
#include <vrsph/moving/operators.hpp>

namespace vrsph {

/// The operators' Laplacian as a matrix (a copy): what PressurePoisson factorises.
/// ConfigError when they keep no Laplacian or it has right-hand-side weights (compact rows: a
/// projection needs the operator's value at each particle).
CsrMatrix laplacian_matrix(const Operators& ops);

/// The wall particles of a cloud (tag Dirichlet) and their outward unit normals (none on a
/// periodic box). InputError for a wall particle without a unit normal, ConfigError for
/// Neumann or Ghost particles (a flow has no use for them).
struct Walls {
  std::vector<Index> index;
  std::vector<Vec3> normal;
  std::vector<char> is_wall;  ///< per particle (empty when there are no walls)
  bool empty() const { return index.empty(); }
};
Walls walls_of(const PointCloud& cloud);

/// The pressure matrix: the Laplacian's rows at fluid particles, the Neumann rows n·G at walls
/// (every row annihilates constants, as PressurePoisson requires).
CsrMatrix pressure_matrix(const Operators& ops, const Walls& walls);
/// Its right-hand side for a pressure that balances the acceleration a (N x d): D a at fluid
/// particles, n·a at walls.
Field pressure_rhs(const Operators& ops, const Walls& walls, const Eigen::MatrixXd& a);
/// The pressure equation of these operators and walls, factorised: pressure_matrix, pinned at
/// the first fluid particle; with walls its defect spread along the left null vector
/// (pressure_poisson.hpp), one more factorisation (of the transpose) at set-up.
PressurePoisson pressure_poisson(const Operators& ops, const Walls& walls, const SolverOptions& options);

struct Projected {
  Eigen::MatrixXd u;  ///< w - G φ
  Field phi;          ///< the potential removed (zero mean)
  Real shift = 0;     ///< PressurePoisson::Result::shift
  SolveReport report;
};

/// w projected with the operators' L (factorised in `ppe`: pressure_matrix with these walls),
/// G and D; wall particles keep w. `phi_guess`: an initial guess for an iterative solver
/// (empty: none). InputError for a w of another shape.
Projected project(const Operators& ops, const PressurePoisson& ppe, const Eigen::MatrixXd& w, const Field& phi_guess = {},
                  const Walls& walls = {});

/// (u · G) u: the advection of u (N x d) by itself with the operators' gradient, N x d.
Eigen::MatrixXd advection(const Operators& ops, const Eigen::MatrixXd& u);

}  // namespace vrsph
