// Eigen's direct and iterative solvers and UMFPACK; the heavy solver headers live only here.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>
#include <chrono>
#include <vrsph/core/error.hpp>
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
void direct(const LinearSystem& sys, Eigen::VectorXd& x, SolveReport& rep) {
  const auto t0 = std::chrono::steady_clock::now();
  // The factorisations want compressed columns; UMFPACK keeps pointers into the matrix
  // until the solve, so the copy lives as long as the factorisation.
  const Eigen::SparseMatrix<Real> columns(sys.A);
  Direct lu;
  lu.compute(columns);
  rep.seconds_setup = since(t0);
  if (lu.info() != Eigen::Success) {
    rep.reason = "factorisation_failed";
    rep.message = "factorisation failed (singular or ill-conditioned matrix)";
    return;
  }
  x = lu.solve(sys.b);
  rep.iterations = 1;
  rep.success = lu.info() == Eigen::Success;
  rep.reason = rep.success ? "direct" : "back_substitution_failed";
  if (!rep.success) rep.message = "back-substitution failed";
}
}  // namespace

void solve_eigen(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep) {
  switch (o.type) {
    case SolverType::SparseLU:
      direct<Eigen::SparseLU<Eigen::SparseMatrix<Real>, Eigen::COLAMDOrdering<int>>>(sys, x, rep);
      return;
    case SolverType::UmfPack:
      direct<Eigen::UmfPackLU<Eigen::SparseMatrix<Real>>>(sys, x, rep);
      return;
    case SolverType::BiCGSTAB: {
      const auto t0 = std::chrono::steady_clock::now();
      Eigen::BiCGSTAB<CsrMatrix, Eigen::IncompleteLUT<Real>> it;
      it.preconditioner().setDroptol(o.ilut_drop);
      it.preconditioner().setFillfactor(o.ilut_fill);
      it.setTolerance(o.rtol);
      it.setMaxIterations(o.max_iterations);
      it.compute(sys.A);
      rep.seconds_setup = since(t0);
      if (it.info() != Eigen::Success) {
        rep.reason = "preconditioner_failed";
        rep.message = "incomplete LUT preconditioner failed";
        return;
      }
      x = it.solve(sys.b);
      rep.iterations = static_cast<int>(it.iterations());
      rep.success = it.info() == Eigen::Success;
      rep.reason = rep.success ? "converged" : "not_converged";
      if (o.monitor) o.monitor(rep.iterations, it.error());  // Eigen reports only the final estimate
      if (!rep.success)
        rep.message = detail::concat("BiCGSTAB did not converge in ", it.iterations(), " iterations (estimated error ",
                                     it.error(), ")");
      return;
    }
    default: throw ConfigError(detail::concat("solver ", to_string(o.type), " is not an Eigen solver"));
  }
}

}  // namespace vrsph::detail
