// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the solver back-ends behind vrsph::solve and vrsph::PreparedSolver. A back-end
// is set up once for a matrix (factorisation, preconditioner) and then solves any number
// of right-hand sides; each solve fills x and the report's success, reason, message,
// iterations and history. The dispatcher (solver.cpp) checks memory up front and measures
// the true residual afterwards.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph::detail {

/// The dimension the solver assumes when the caller gave none: 3, the fastest-growing LU
/// fill-in estimate and the smallest direct-solve limit of `auto`. (It cannot be read off the
/// row lengths: with exact zeros dropped, a 2D VRSPH row has ~10 entries, a 1D SPH row ~7.)
inline int assumed_dimension(int dimension) { return dimension > 0 ? dimension : 3; }

/// One matrix, set up. The matrix it was prepared for must outlive it (it is borrowed).
class Backend {
 public:
  virtual ~Backend() = default;
  /// x on entry: the initial guess of iterative back-ends (size 0: zero); on exit: the solution.
  virtual void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep) = 0;
  /// Solves with another matrix A of the same size, preconditioned by this set-up (PETSc: the
  /// AMG hierarchy of this matrix, on one rank); false if the back-end cannot (the caller then
  /// preconditions a Krylov method of its own with solve()).
  virtual bool solve_other(const CsrMatrix& /*A*/, const Eigen::VectorXd& /*b*/, Eigen::VectorXd& /*x*/,
                           SolveReport& /*rep*/, Real /*rtol*/, int /*max_iterations*/) {
    return false;
  }
  std::string name;                   ///< "umfpack", "petsc gmres+hypre(boomeramg)", ...
  double seconds_setup = 0;
  bool ready = true;                  ///< false: the set-up failed (reason and message below)
  std::string reason, message;        ///< of a failed set-up
  std::vector<std::string> warnings;  ///< from the set-up (e.g. PETSc options never used)
};

/// ||b - A x|| / ||b|| (||b|| = 0: the residual's norm itself).
inline Real relative_residual(const CsrMatrix& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const Real bnorm = b.norm();
  return (b - A * x).norm() / (bnorm > 0 ? bnorm : 1.0);
}

/// A back-end's "converged" is not taken on trust: a true relative residual (rep.residual) that
/// is not finite or not below max(1e-6, 100 rtol) fails the solve.
inline void reject_large_residual(SolveReport& rep, Real rtol) {
  if (rep.success && !(std::isfinite(rep.residual) && rep.residual < std::max(1e-6, 100 * rtol))) {
    rep.success = false;
    rep.message = concat("true relative residual ", rep.residual, " too large");
  }
}

/// SparseLU, UMFPACK or BiCGSTAB + ILUT (o.type).
std::unique_ptr<Backend> prepare_eigen(const CsrMatrix& A, const SolverOptions& o);
/// PETSc KSP + PC from vrsph's defaults, PETSC_OPTIONS and o.petsc_options.
std::unique_ptr<Backend> prepare_petsc(const CsrMatrix& A, const SolverOptions& o);

}  // namespace vrsph::detail
