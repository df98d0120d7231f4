// SPDX-License-Identifier: BSD-3-Clause
// Eigen's direct and iterative solvers and UMFPACK; the heavy solver headers live only here.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <chrono>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#if VRSPH_HAVE_SUITESPARSE
#include <Eigen/UmfPackSupport>
#endif
#include "backends.hpp"

// GCC 12 reports a null dereference inside Eigen's nonZeros() when BiCGSTAB's compute is
// inlined on a row-major matrix: a false positive (the matrix is compressed, its outer
// index array allocated), so it is silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wnull-dereference"
#endif

namespace vrsph::detail {

namespace {
double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class Direct>
class DirectBackend final : public Backend {
 public:
  DirectBackend(const CsrMatrix& A, const char* solver_name) : columns_(A) {
    // The factorisations want compressed columns; UMFPACK keeps pointers into the matrix
    // until the solve, so the copy lives as long as the factorisation.
    name = solver_name;
    const auto t0 = std::chrono::steady_clock::now();
    lu_.compute(columns_);
    seconds_setup = since(t0);
    if (lu_.info() != Eigen::Success) {
      ready = false;
      reason = "factorisation_failed";
      message = "factorisation failed (singular or ill-conditioned matrix)";
    }
  }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep) override {
    x = lu_.solve(b);
    rep.iterations = 1;
    rep.success = lu_.info() == Eigen::Success;
    rep.reason = rep.success ? "direct" : "back_substitution_failed";
    if (!rep.success) rep.message = "back-substitution failed";
  }

 private:
  Eigen::SparseMatrix<Real> columns_;
  Direct lu_;
};

class BicgstabBackend final : public Backend {
 public:
  BicgstabBackend(const CsrMatrix& A, const SolverOptions& o) : monitor_(o.monitor) {
    name = "bicgstab";
    const auto t0 = std::chrono::steady_clock::now();
    it_.preconditioner().setDroptol(o.ilut_drop);
    it_.preconditioner().setFillfactor(o.ilut_fill);
    it_.setTolerance(o.rtol);
    it_.setMaxIterations(o.max_iterations);
    it_.compute(A);  // keeps a reference to A: the caller's matrix outlives the back-end
    seconds_setup = since(t0);
    if (it_.info() != Eigen::Success) {
      ready = false;
      reason = "preconditioner_failed";
      message = "incomplete LUT preconditioner failed";
    }
  }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep) override {
    if (x.size() == b.size()) x = it_.solveWithGuess(b, Eigen::VectorXd(x));
    else x = it_.solve(b);
    rep.iterations = static_cast<int>(it_.iterations());
    rep.success = it_.info() == Eigen::Success;
    rep.reason = rep.success ? "converged" : "not_converged";
    if (monitor_) monitor_(rep.iterations, it_.error());  // Eigen reports only the final estimate
    if (!rep.success)
      rep.message = detail::concat("BiCGSTAB did not converge in ", it_.iterations(), " iterations (estimated error ",
                                   it_.error(), ")");
  }

 private:
  Eigen::BiCGSTAB<CsrMatrix, Eigen::IncompleteLUT<Real>> it_;
  std::function<void(int, Real)> monitor_;
};
}  // namespace

std::unique_ptr<Backend> prepare_eigen(const CsrMatrix& A, const SolverOptions& o) {
  switch (o.type) {
    case SolverType::SparseLU:
      return std::make_unique<DirectBackend<Eigen::SparseLU<Eigen::SparseMatrix<Real>, Eigen::COLAMDOrdering<int>>>>(
          A, "sparselu");
    case SolverType::UmfPack:
#if VRSPH_HAVE_SUITESPARSE
      return std::make_unique<DirectBackend<Eigen::UmfPackLU<Eigen::SparseMatrix<Real>>>>(A, "umfpack");
#else
      require_part("SUITESPARSE", "--solver umfpack");
      return nullptr;  // not reached: the part is not built
#endif
    case SolverType::BiCGSTAB: return std::make_unique<BicgstabBackend>(A, o);
    default: throw ConfigError(detail::concat("solver ", to_string(o.type), " is not an Eigen solver"));
  }
}

}  // namespace vrsph::detail
