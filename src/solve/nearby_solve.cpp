// SPDX-License-Identifier: BSD-3-Clause
// PreparedSolver::solve_nearby: a set-up of one matrix preconditioning a nearby one (solver.hpp).
#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <vrsph/core/error.hpp>
#include <vrsph/solve/solver.hpp>
#include "backends.hpp"

namespace vrsph {

namespace {
// Eigen's preconditioner concept over a PreparedSolver: compute() does nothing (the solver is
// set up for its own matrix already), solve() is the prepared solve.
class PreparedPreconditioner {
 public:
  PreparedPreconditioner() = default;
  template <class M>
  explicit PreparedPreconditioner(const M&) {}
  template <class M>
  PreparedPreconditioner& analyzePattern(const M&) {
    return *this;
  }
  template <class M>
  PreparedPreconditioner& factorize(const M&) {
    return *this;
  }
  template <class M>
  PreparedPreconditioner& compute(const M&) {
    return *this;
  }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    Eigen::VectorXd rhs = b, x;
    const SolveReport r = prepared->solve(rhs, x);
    if (!r.success) failed = true;  // BiCGSTAB then stops with a failed report (below)
    return x;
  }
  Eigen::ComputationInfo info() { return Eigen::Success; }

  const PreparedSolver* prepared = nullptr;
  mutable bool failed = false;
};
}  // namespace

SolveReport PreparedSolver::solve_nearby(const CsrMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x, Real rtol,
                                         int max_iterations) const {
  check<InputError>(A.rows() == A_->rows() && A.cols() == A_->cols(), "solver: a nearby matrix of ", A.rows(), " x ",
                    A.cols(), " for a solver of ", A_->rows(), " unknowns");
  check<InputError>(b.size() == A.rows() && b.allFinite(), "solver: the right-hand side is not finite or of size ",
                    b.size(), " for ", A.rows(), " unknowns");
  check<ConfigError>(rtol > 0 && max_iterations > 0, "solver: tolerance and iteration cap must be positive");
  const auto t0 = std::chrono::steady_clock::now();
  if (reuses_hierarchy()) {
    SolveReport rep;
    rep.solver = backend_->name + " (preconditioner of an earlier matrix)";
    if (x.size() != b.size()) x = Eigen::VectorXd::Zero(b.size());
    if (backend_->solve_other(A, b, x, rep, rtol, max_iterations)) {
      rep.residual = detail::relative_residual(A, b, x);
      detail::reject_large_residual(rep, rtol);
      rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return rep;
    }
  }
  Eigen::BiCGSTAB<CsrMatrix, PreparedPreconditioner> it;
  it.preconditioner().prepared = this;
  it.setTolerance(rtol);
  it.setMaxIterations(max_iterations);
  it.compute(A);  // A's reference and the (empty) preconditioner set-up
  if (x.size() == b.size()) x = it.solveWithGuess(b, Eigen::VectorXd(x));
  else x = it.solve(b);
  SolveReport rep;
  rep.solver = "bicgstab preconditioned by " + solver();
  rep.iterations = static_cast<int>(it.iterations());
  rep.residual = detail::relative_residual(A, b, x);
  rep.success = it.info() == Eigen::Success && !it.preconditioner().failed && x.allFinite() &&
                rep.residual <= std::max(1e-6, 100 * rtol);
  rep.reason = rep.success ? "converged" : "not_converged";
  if (!rep.success)
    rep.message = detail::concat("BiCGSTAB on the nearby matrix reached a true relative residual of ", rep.residual,
                                 " in ", rep.iterations, " iterations", it.preconditioner().failed ? " (a preconditioner "
                                 "solve failed)" : "");
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace vrsph
