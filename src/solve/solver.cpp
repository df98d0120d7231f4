// SPDX-License-Identifier: BSD-3-Clause
// Solver choice, memory check and the true-residual check common to every back-end.
#include <chrono>
#include <cmath>
#include <limits>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include "backends.hpp"

namespace vrsph {

SolverType parse_solver(const std::string& name) {
  if (name == "auto") return SolverType::Auto;
  if (name == "sparselu" || name == "lu") return SolverType::SparseLU;
  if (name == "umfpack") return SolverType::UmfPack;
  if (name == "bicgstab") return SolverType::BiCGSTAB;
  if (name == "petsc") return SolverType::Petsc;
  throw ConfigError("unknown solver '" + name + "' (known: auto, petsc, sparselu, umfpack, bicgstab)");
}

std::string to_string(SolverType t) {
  switch (t) {
    case SolverType::Auto: return "auto";
    case SolverType::SparseLU: return "sparselu";
    case SolverType::UmfPack: return "umfpack";
    case SolverType::BiCGSTAB: return "bicgstab";
    case SolverType::Petsc: return "petsc";
  }
  return "?";
}

Index auto_direct_limit(int dimension) {
  // Whole `vrsph study` runs on VRSPH Example 5, PETSc's ~0.3 s start-up included, take the
  // same time with UMFPACK and with GMRES + BoomerAMG at ~4 10^4 unknowns in 2D (n = 200)
  // and between 3.4k and 6.9k in 3D; the limits sit below that because UMFPACK's memory
  // grows faster than its time (docs/solvers.md). 1D matrices are banded (fill-in O(nnz)).
  if (dimension == 1) return std::numeric_limits<Index>::max();
  // Without PETSc the iterative choice is BiCGSTAB + ILUT. In 2D it was no faster than the direct
  // solve at 2.5e4 and 1e5 unknowns, and its stop at a relative residual of 1e-10 left errors
  // 100-1000 times the discretisation's (u = e^x sin 2y + x^2, a = 1 + xy, perturbed: 3.6e-8
  // against 3.0e-10 at n = 160, 2.6e-8 against 2.5e-11 at n = 320; docs/solvers.md). In 3D it is
  // 2-4 times faster with the direct solve's errors: the limit stays.
  if (dimension == 2) return VRSPH_HAVE_PETSC ? 20000 : 250000;
  return 4000;
}

SolverType auto_direct_solver() { return VRSPH_HAVE_SUITESPARSE ? SolverType::UmfPack : SolverType::SparseLU; }

SolverType resolve_auto(Index unknowns, int dimension, Index direct_max) {
  const Index limit = direct_max > 0 ? direct_max : auto_direct_limit(dimension);
  // Without PETSc, BiCGSTAB + ILUT above the limit: slower than AMG, but it needs no memory
  // for a factorisation (docs/solvers.md).
  const SolverType iterative = VRSPH_HAVE_PETSC ? SolverType::Petsc : SolverType::BiCGSTAB;
  return unknowns <= limit ? auto_direct_solver() : iterative;
}

double direct_solver_bytes(const CsrMatrix& A, int dimension) {
  const auto n = static_cast<double>(A.rows()), nnz = static_cast<double>(A.nonZeros());
  dimension = detail::assumed_dimension(dimension);
  // Measured (peak RSS above the iterative solver's, vrsph study --solver ...):
  // 2D 160k unknowns: SparseLU 1.1 GB, UMFPACK 0.12 GB; 3D 59k: 3.2 GB, 1.7 GB.
  if (dimension == 1) return 50 * nnz + 1e6;
  if (dimension == 2) return 5 * nnz * std::cbrt(n) + 1e6;
  return 0.6 * nnz * std::pow(n, 2.0 / 3.0) + 1e6;
}

namespace {
std::unique_ptr<detail::Backend> prepare(const CsrMatrix& A, const SolverOptions& o) {
  if (o.type == SolverType::SparseLU || o.type == SolverType::UmfPack)
    check_memory_estimate(direct_solver_bytes(A, o.dimension),
                          detail::concat("the sparse LU factorisation (", to_string(o.type), ", ", A.rows(),
                                         " unknowns, ", A.nonZeros(), " nonzeros)"),
                          "use an iterative solver (--solver petsc), or fewer particles");
  return o.type == SolverType::Petsc ? detail::prepare_petsc(A, o) : detail::prepare_eigen(A, o);
}

// One solve with a prepared back-end, with the true residual checked.
SolveReport solve_prepared(detail::Backend& backend, const CsrMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                           const SolverOptions& o) {
  SolveReport rep;
  rep.solver = backend.name;
  rep.warnings = backend.warnings;
  rep.seconds_setup = backend.seconds_setup;
  if (!backend.ready) {
    rep.reason = backend.reason;
    rep.message = backend.message;
    x = Eigen::VectorXd::Zero(A.rows());
    return rep;
  }
  backend.solve(b, x, rep);
  // Distributed: the back-end measured it over every rank.
  if (!o.communicator.distributed()) rep.residual = detail::relative_residual(A, b, x);
  detail::reject_large_residual(rep, o.rtol);
  return rep;
}

// One back-end run of the resolved type from a zero initial guess.
SolveReport solve_with(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o) {
  const auto backend = prepare(sys.A, o);
  x = Eigen::VectorXd::Zero(sys.A.rows());
  return solve_prepared(*backend, sys.A, sys.b, x, o);
}

SolverOptions resolved(const SolverOptions& options, Index unknowns) {  // unknowns: this rank's
  check<ConfigError>(options.rtol > 0 && options.max_iterations > 0, "solver tolerance and iteration cap must be positive");
  SolverOptions o = options;
  o.dimension = detail::assumed_dimension(o.dimension);
  if (o.communicator.distributed()) {
    check<ConfigError>(o.type == SolverType::Auto || o.type == SolverType::Petsc, "solver ", to_string(o.type),
                       " runs on one rank only; with ", o.communicator.size(), " MPI ranks use --solver petsc (or auto)");
    o.type = SolverType::Petsc;
  }
  if (o.type == SolverType::Auto) o.type = resolve_auto(unknowns, o.dimension, o.auto_direct_max);
  return o;
}

constexpr int auto_iteration_cap = 500;
}  // namespace

SolveReport solve(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& options) {
  SolverOptions o = resolved(options, sys.size());
  const auto t0 = std::chrono::steady_clock::now();
  const bool automatic = options.type == SolverType::Auto;
  // auto gives AMG a bounded number of iterations: the defaults are tuned for M-matrices
  // (VRSPH, SPH) and converge in ~10-25; a matrix they do not suit (FPM's mixed signs) is
  // then handed to the direct solver below instead of iterating to the cap of 20 000.
  if (automatic && o.type == SolverType::Petsc && !o.communicator.distributed()) o.max_iterations = std::min(o.max_iterations, auto_iteration_cap);
  SolveReport rep = solve_with(sys, x, o);
  if (automatic && o.type == SolverType::Petsc && !rep.success && !o.communicator.distributed()) {
    bool fits = true;
    try {
      check_memory_estimate(direct_solver_bytes(sys.A, o.dimension), "the fallback direct solve", "");
    } catch (const ResourceError&) {
      fits = false;
    }
    if (fits) {
      const std::string why = rep.reason.empty() ? rep.message : rep.reason;
      SolverOptions direct = o;
      direct.type = auto_direct_solver();
      std::vector<std::string> warnings = std::move(rep.warnings);
      rep = solve_with(sys, x, direct);
      rep.solver = to_string(direct.type) + " after petsc (" + why + ")";
      warnings.push_back(detail::concat("auto: PETSc GMRES + BoomerAMG did not converge (", why,
                                        "); solved with ", direct.type == SolverType::UmfPack ? "UMFPACK" : "Eigen's SparseLU",
                                        " instead. The AMG defaults suit M-matrices "
                                        "(vrsph, sph); give --solver and --petsc-options to choose otherwise"));
      rep.warnings.insert(rep.warnings.begin(), warnings.begin(), warnings.end());
    }
  }
  if (automatic) rep.solver = "auto: " + rep.solver;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

PreparedSolver::PreparedSolver(const CsrMatrix& A, const SolverOptions& options)
    : A_(std::make_unique<const CsrMatrix>(A)), options_(resolved(options, static_cast<Index>(A.rows()))) {
  check<InputError>(options.communicator.distributed() || A_->rows() == A_->cols(), "solver: the matrix is ", A_->rows(),
                    " x ", A_->cols(), ", not square");
  backend_ = prepare(*A_, options_);
  if (options.type == SolverType::Auto) backend_->name = "auto: " + backend_->name;
  if (!backend_->ready)
    throw NumericalError(detail::concat("solver ", backend_->name, " could not be set up: ", backend_->message));
}

PreparedSolver::~PreparedSolver() = default;
PreparedSolver::PreparedSolver(PreparedSolver&&) noexcept = default;
PreparedSolver& PreparedSolver::operator=(PreparedSolver&&) noexcept = default;

SolveReport PreparedSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  check<InputError>(b.size() == A_->rows(), "solver: right-hand side of size ", b.size(), " for ", A_->rows(), " unknowns");
  check<InputError>(b.allFinite(), "solver: the right-hand side is not finite");
  const auto t0 = std::chrono::steady_clock::now();
  SolveReport rep = solve_prepared(*backend_, *A_, b, x, options_);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

const std::string& PreparedSolver::solver() const { return backend_->name; }
double PreparedSolver::seconds_setup() const { return backend_->seconds_setup; }

}  // namespace vrsph
