// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The implicit viscous stage of an IMEX Runge–Kutta flow step (flow_solver.hpp,
// FlowViscosity::Implicit): (I - c L) U = R for each velocity component, c = a dt ν (a the
// scheme's diagonal coefficient), L the operators' Laplacian on the fluid particles, and
// identity rows at the walls (their velocity is prescribed: U = R there). The matrix is set
// up once per c and positions. While c ρ(L) (ρ bounded by the rows' absolute sums) is at most
// jacobi_limit the system is strongly diagonally dominant and BiCGSTAB with the diagonal as
// preconditioner solves it in a few iterations with no set-up (moving particles change the
// matrix at every stage); beyond, the pressure's SolverOptions set it up once (a factorisation
// or AMG), which a fixed cloud at a fixed time step then reuses for every stage and component.
#include <memory>
#include <vector>
#include <vrsph/flow/projection.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

/// The ARS IMEX Runge–Kutta tableaux (Ascher, Ruuth & Spiteri, Appl. Numer. Math. 25 (1997)
/// 151–167): ARS(2,2,2), second order, and ARS(4,4,3), third order; both with an L-stable,
/// singly diagonal implicit part (one matrix per time step) and stiffly accurate (the last
/// stage is the step's result). Row i of `explicit_a`/`implicit_a` gives stage i from the
/// stages before it (and itself, implicit); stage 0 is the step's start; c the stage times.
struct ImexTableau {
  int stages = 0;
  std::vector<std::vector<Real>> explicit_a, implicit_a;
  std::vector<Real> c;
  Real diagonal = 0;            ///< the implicit diagonal of stages 1.. (singly diagonal)
  Real imaginary_limit = 0;     ///< the explicit part's stability interval along the imaginary axis
  Real real_limit = 0;          ///< ... along the negative real axis
};
const ImexTableau& ars222();
const ImexTableau& ars443();

class ImplicitViscosity {
 public:
  /// The largest c ρ(L) solved by Jacobi-preconditioned BiCGSTAB. Measured on the Taylor–Green
  /// vortex at nx = 128, CFL 0.25 (docs/flow.md): 4, 13 and 43 iterations a solve at Re = 100,
  /// 10 and 1.
  static constexpr Real jacobi_limit = 200;
  /// Sets up (I - c L) with the walls' identity rows for the operators' current positions.
  /// c >= 0 finite (ConfigError). Throws as PreparedSolver.
  ImplicitViscosity(const Operators& ops, const Walls& walls, Real c, const SolverOptions& options);
  /// Solves (I - c L) U = R column by column (R: N x d); `guess` an initial guess for an
  /// iterative solver (empty: R). NumericalError naming the component when a solve fails.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& R, const Eigen::MatrixXd& guess = {}) const;
  Real coefficient() const { return c_; }
  bool jacobi() const { return !solver_; }  ///< BiCGSTAB with the diagonal preconditioner (no set-up)
  int iterations() const { return iterations_; }  ///< over the solves so far

 private:
  Real c_ = 0;
  Real rtol_ = 1e-10;
  int max_iterations_ = 1000;
  CsrMatrix matrix_;                       ///< I - c L with the walls' identity rows
  std::unique_ptr<PreparedSolver> solver_;  ///< beyond jacobi_limit
  mutable int iterations_ = 0;
};

}  // namespace vrsph
