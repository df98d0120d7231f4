// Direct and iterative solvers; the heavy Eigen solver headers live only here.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>
#include <chrono>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

SolverType parse_solver(const std::string& name) {
  if (name == "sparselu" || name == "lu") return SolverType::SparseLU;
  if (name == "umfpack") return SolverType::UmfPack;
  if (name == "bicgstab") return SolverType::BiCGSTAB;
  throw ConfigError("unknown solver '" + name + "' (known: sparselu, umfpack, bicgstab)");
}

std::string to_string(SolverType t) {
  switch (t) {
    case SolverType::SparseLU: return "sparselu";
    case SolverType::UmfPack: return "umfpack";
    case SolverType::BiCGSTAB: return "bicgstab";
  }
  return "?";
}

double direct_solver_bytes(const CsrMatrix& A, int dimension) {
  const auto n = static_cast<double>(A.rows()), nnz = static_cast<double>(A.nonZeros());
  if (dimension <= 0) {
    const double per_row = nnz / std::max(n, 1.0);
    dimension = per_row <= 15 ? 1 : per_row <= 50 ? 2 : 3;
  }
  // Measured (peak RSS above the iterative solver's, vrsph study --solver ...):
  // 2D 160k unknowns: SparseLU 1.1 GB, UMFPACK 0.12 GB; 3D 59k: 3.2 GB, 1.7 GB.
  if (dimension == 1) return 50 * nnz + 1e6;
  if (dimension == 2) return 5 * nnz * std::cbrt(n) + 1e6;
  return 0.6 * nnz * std::pow(n, 2.0 / 3.0) + 1e6;
}

namespace {
template <class Direct>
void direct(const LinearSystem& sys, Eigen::VectorXd& x, SolveReport& rep) {
  // The factorisations want compressed columns; UMFPACK keeps pointers into the matrix
  // until the solve, so the copy lives as long as the factorisation.
  const Eigen::SparseMatrix<Real> columns(sys.A);
  Direct lu;
  lu.compute(columns);
  if (lu.info() != Eigen::Success) {
    rep.message = "factorisation failed (singular or ill-conditioned matrix)";
    return;
  }
  x = lu.solve(sys.b);
  rep.iterations = 1;
  rep.success = lu.info() == Eigen::Success;
  if (!rep.success) rep.message = "back-substitution failed";
}
}  // namespace

SolveReport solve(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o) {
  check<ConfigError>(o.rtol > 0 && o.max_iterations > 0, "solver tolerance and iteration cap must be positive");
  if (o.type == SolverType::SparseLU || o.type == SolverType::UmfPack)
    check_memory_estimate(direct_solver_bytes(sys.A, o.dimension),
                          detail::concat("the sparse LU factorisation (", to_string(o.type), ", ", sys.A.rows(),
                                         " unknowns, ", sys.A.nonZeros(), " nonzeros)"),
                          "use the iterative solver (--solver bicgstab), or fewer particles");
  const auto t0 = std::chrono::steady_clock::now();
  SolveReport rep;
  rep.solver = to_string(o.type);
  x = Eigen::VectorXd::Zero(sys.size());
  switch (o.type) {
    case SolverType::SparseLU:
      direct<Eigen::SparseLU<Eigen::SparseMatrix<Real>, Eigen::COLAMDOrdering<int>>>(sys, x, rep);
      break;
    case SolverType::UmfPack:
      direct<Eigen::UmfPackLU<Eigen::SparseMatrix<Real>>>(sys, x, rep);
      break;
    case SolverType::BiCGSTAB: {
      Eigen::BiCGSTAB<Eigen::SparseMatrix<Real>, Eigen::IncompleteLUT<Real>> it;
      it.preconditioner().setDroptol(o.ilut_drop);
      it.preconditioner().setFillfactor(o.ilut_fill);
      it.setTolerance(o.rtol);
      it.setMaxIterations(o.max_iterations);
      it.compute(sys.A);
      if (it.info() != Eigen::Success) {
        rep.message = "incomplete LUT preconditioner failed";
        break;
      }
      x = it.solve(sys.b);
      rep.iterations = static_cast<int>(it.iterations());
      rep.success = it.info() == Eigen::Success;
      if (!rep.success)
        rep.message = detail::concat("BiCGSTAB did not converge in ", it.iterations(), " iterations (estimated error ",
                                     it.error(), ")");
      break;
    }
  }
  const Real bnorm = sys.b.norm();
  rep.residual = (sys.b - sys.A * x).norm() / (bnorm > 0 ? bnorm : 1.0);
  if (rep.success && !(std::isfinite(rep.residual) && rep.residual < std::max(1e-6, 100 * o.rtol))) {
    rep.success = false;
    rep.message = detail::concat("true relative residual ", rep.residual, " too large");
  }
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace vrsph
