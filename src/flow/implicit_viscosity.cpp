// SPDX-License-Identifier: BSD-3-Clause
// The implicit viscous stage of the IMEX flow step (implicit_viscosity.hpp).
#include <algorithm>
#include <cmath>
#include <Eigen/IterativeLinearSolvers>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/implicit_viscosity.hpp>

namespace vrsph {

const ImexTableau& ars222() {
  // ARS(2,2,2): γ = 1 - 1/√2, δ = 1 - 1/(2γ). The explicit part is, like Heun's method, stable
  // on no interval of the imaginary axis: the advective limit of 1 relies on the viscosity
  // (as FlowScheme::RK2's does).
  static const ImexTableau t = [] {
    const Real g = 1 - 1 / std::sqrt(2.0), d = 1 - 1 / (2 * g);
    ImexTableau s;
    s.stages = 3;
    s.explicit_a = {{}, {g}, {d, 1 - d}};
    s.implicit_a = {{}, {0, g}, {0, 1 - g, g}};
    s.c = {0, g, 1};
    s.diagonal = g;
    s.imaginary_limit = 1.0;
    s.real_limit = 2.0;
    return s;
  }();
  return t;
}

const ImexTableau& ars443() {
  // ARS(4,4,3): the explicit part reaches 1.57 along the imaginary axis and 2.14 along the
  // negative real one (computed from its stability function; RK3's: √3 and 2.51).
  static const ImexTableau t = [] {
    ImexTableau s;
    s.stages = 5;
    s.explicit_a = {{}, {0.5}, {11.0 / 18, 1.0 / 18}, {5.0 / 6, -5.0 / 6, 0.5}, {0.25, 1.75, 0.75, -1.75}};
    s.implicit_a = {{}, {0, 0.5}, {0, 1.0 / 6, 0.5}, {0, -0.5, 0.5, 0.5}, {0, 1.5, -1.5, 0.5, 0.5}};
    s.c = {0, 0.5, 2.0 / 3, 0.5, 1};
    s.diagonal = 0.5;
    s.imaginary_limit = 1.57;
    s.real_limit = 2.14;
    return s;
  }();
  return t;
}

ImplicitViscosity::ImplicitViscosity(const Operators& ops, const Walls& walls, Real c, const SolverOptions& options)
    : c_(c), rtol_(options.rtol), max_iterations_(options.max_iterations) {
  check<ConfigError>(std::isfinite(c) && c >= 0, "flow: the implicit viscous coefficient must be finite and >= 0, got ", c);
  const CsrMatrix L = laplacian_matrix(ops);
  const auto n = static_cast<Index>(L.rows());
  std::vector<Eigen::Triplet<Real>> t;
  t.reserve(static_cast<std::size_t>(L.nonZeros() + n));
  Real bound = 0;  // max_i Σ_j |L_ij| over the fluid rows: ρ(L) at most this (Gershgorin)
  for (Index i = 0; i < n; ++i) {
    t.emplace_back(i, i, 1.0);
    if (!walls.empty() && walls.is_wall[static_cast<std::size_t>(i)]) continue;
    Real sum = 0;
    for (CsrMatrix::InnerIterator it(L, i); it; ++it) {
      t.emplace_back(i, it.col(), -c * it.value());
      sum += std::abs(it.value());
    }
    bound = std::max(bound, sum);
  }
  matrix_ = CsrMatrix(n, n);
  matrix_.setFromTriplets(t.begin(), t.end());
  if (c * bound > jacobi_limit) solver_ = std::make_unique<PreparedSolver>(matrix_, options);
}

Eigen::MatrixXd ImplicitViscosity::solve(const Eigen::MatrixXd& R, const Eigen::MatrixXd& guess) const {
  check<InputError>(R.rows() == matrix_.rows(), "flow: a viscous right-hand side of ", R.rows(), " rows for ",
                    matrix_.rows(), " particles");
  Eigen::MatrixXd U(R.rows(), R.cols());
  std::unique_ptr<Eigen::BiCGSTAB<CsrMatrix, Eigen::DiagonalPreconditioner<Real>>> jacobi;
  if (!solver_) {
    jacobi = std::make_unique<Eigen::BiCGSTAB<CsrMatrix, Eigen::DiagonalPreconditioner<Real>>>(matrix_);
    jacobi->setTolerance(rtol_);
    jacobi->setMaxIterations(max_iterations_);
  }
  for (Eigen::Index c = 0; c < R.cols(); ++c) {
    Eigen::VectorXd x = guess.size() == R.size() ? Eigen::VectorXd(guess.col(c)) : Eigen::VectorXd(R.col(c));
    if (jacobi) {
      x = jacobi->solveWithGuess(R.col(c), x);
      check<NumericalError>(jacobi->info() == Eigen::Success, "the implicit viscous solve of velocity component ", c,
                            " failed (BiCGSTAB with the diagonal preconditioner: relative residual ", jacobi->error(),
                            " after ", jacobi->iterations(), " iterations)");
      iterations_ += static_cast<int>(jacobi->iterations());
    } else {
      const SolveReport rep = solver_->solve(R.col(c), x);
      check<NumericalError>(rep.success, "the implicit viscous solve of velocity component ", c, " failed (", rep.solver,
                            ": ", rep.message.empty() ? rep.reason : rep.message, ")");
      iterations_ += rep.iterations;
    }
    U.col(c) = x;
  }
  return U;
}

}  // namespace vrsph
