// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Sparse linear solvers for assembled systems. Non-convergence is a returned status
// (SolveReport::success), never an exception; callers decide (the studies turn a
// failed solve into a NumericalError, never a silent result). Bad solver options
// (an unknown solver, options PETSc rejects) are a ConfigError.
//
// How to choose:
// - auto (default): a direct solver for small systems, PETSc GMRES + hypre BoomerAMG
//   (tuned for our non-symmetric M-matrices, see default_petsc_options) for large ones;
//   SolveReport::solver says which was picked.
// - petsc: PETSc KSP + PC, default GMRES + BoomerAMG; any PETSc option can be given
//   (SolverOptions::petsc_options, and the PETSC_OPTIONS environment variable).
//   Iteration counts stay flat with the size, so it is the solver for 10^5+ unknowns.
// - sparselu (Eigen), umfpack (SuiteSparse): direct; memory grows like the LU fill-in.
// - bicgstab: Eigen BiCGSTAB + incomplete LUT, the embedded fallback without PETSc.
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph {

enum class SolverType { Auto, SparseLU, UmfPack, BiCGSTAB, Petsc };
/// "auto" | "sparselu" | "umfpack" | "bicgstab" | "petsc"; throws ConfigError otherwise.
SolverType parse_solver(const std::string& name);
std::string to_string(SolverType t);

struct SolverOptions {
  SolverType type = SolverType::Auto;
  Real rtol = 1e-10;          ///< iterative: relative residual target
  int max_iterations = 20000; ///< iterative
  Real ilut_drop = 1e-5;      ///< bicgstab: incomplete LUT drop tolerance
  int ilut_fill = 20;         ///< bicgstab: incomplete LUT fill factor
  /// PETSc options ("-ksp_type cg -pc_type gamg ..."), applied after the defaults and after
  /// the PETSC_OPTIONS environment variable, so they win over both.
  std::string petsc_options;
  /// Called after every iteration of an iterative solver with (iteration, residual norm
  /// as the solver sees it); empty: no call. The history is in the report either way.
  std::function<void(int, Real)> monitor;
  /// petsc: solve D^-1 A x = D^-1 b with D = diag(A) (a copy of the values; the true
  /// residual is still measured on A x = b). Mixed Dirichlet/Neumann systems need it for
  /// AMG to converge in a size-independent number of iterations (docs/solvers.md).
  bool scale_rows = true;
  /// petsc, with scale_rows: the scaled rows also weighted by an estimate of the matrix's left
  /// null vector (two Jacobi sweeps), so that its columns sum to about zero like its rows:
  /// BoomerAMG's Galerkin coarse levels (R = P^T) then fit our non-symmetric Laplacians
  /// better (about a fifth fewer iterations at 10^6 perturbed particles, docs/solvers.md).
  bool balance_columns = true;
  /// Dimension of the problem's geometry, for the fill-in estimate of the direct solvers,
  /// the direct-solve limit of auto and PETSc's default AMG settings (0: unknown, treated as
  /// 3, the most cautious; a 2D system then gets the 3D settings, which converge but take
  /// about 1.4 x the time).
  int dimension = 0;
  /// The set-up (AMG hierarchy, factorisation) serves many solves: a time stepper's, a flow's
  /// pressure stages. PETSc's defaults then keep the fuller hierarchy whose fewer iterations
  /// repay it (3D: no aggressive coarsening, which suits one solve per set-up; docs/solvers.md).
  bool reused_setup = false;
  /// petsc, on row-scaled systems (scale_rows): BoomerAMG applied as two V-cycles whose
  /// up-sweeps are hybrid Gauss-Seidel, about half the iterations of one Jacobi-smoothed cycle
  /// at the same time (10 against 19 at 10^6 2D particles, docs/solvers.md). False: one cycle,
  /// what the flows' pressure solves keep (pressure_solver_defaults: a reused, stale hierarchy
  /// is a weaker preconditioner, which two cycles compound). Unscaled systems always take one:
  /// where a V-cycle alone diverges (the [SPE] lognormal field's rows as assembled) two of them
  /// broke GMRES down.
  bool two_cycles = true;
  /// auto: the largest system solved directly (0: by dimension, see auto_direct_limit).
  Index auto_direct_max = 0;
  /// The ranks the system is spread over. Distributed (more than one rank): each rank passes
  /// its own rows of A (owned rows x global columns, rows of rank r after those of rank r-1)
  /// and of b, and gets its part of x; only PETSc solves it (auto = petsc, no direct
  /// fallback; sparselu, umfpack, bicgstab are a ConfigError). Default: serial.
  Communicator communicator;
};

/// The largest number of unknowns `auto` solves with a direct solver in dimension d:
/// below it the factorisation is faster than AMG setup + iterations (measured, see
/// docs/solvers.md); 1D systems are banded and always solved directly.
Index auto_direct_limit(int dimension);

/// The solver `auto` picks for a system of this size.
SolverType resolve_auto(Index unknowns, int dimension, Index direct_max = 0);
/// The direct solver `auto` takes: UMFPACK, or Eigen's SparseLU in a build without SuiteSparse.
SolverType auto_direct_solver();

/// The PETSc options vrsph starts from (before PETSC_OPTIONS and the user's): GMRES with
/// BoomerAMG settings tuned for non-symmetric M-matrices of particle Laplacians in
/// dimension d; in 3D, for a set-up that serves one solve (reused_setup false), aggressive
/// coarsening on the first level; with two_cycles (SolverOptions::two_cycles on a row-scaled
/// system), two V-cycles with Gauss-Seidel up-sweeps (docs/solvers.md has the measured tables).
std::string default_petsc_options(int dimension, bool reused_setup = false, bool two_cycles = true);

/// Memory a sparse LU factorisation (SparseLU/COLAMD or UMFPACK) of A is expected to
/// need, in bytes: c nnz(A) N^((d-1)/d), the nested-dissection growth of the fill-in,
/// with c fitted to peak-memory measurements of both solvers on our matrices (2D:
/// N = 40k and 160k; 3D: N = 24k and 59k; within a factor 2 above the measurements).
/// dimension 0: unknown, estimated as 3D (the fastest-growing fill-in).
double direct_solver_bytes(const CsrMatrix& A, int dimension);

struct SolveReport {
  bool success = false;
  std::string solver;         ///< what ran: "umfpack", "petsc gmres+hypre(boomeramg)", ...
  std::string reason;         ///< why it stopped ("converged_rtol", "diverged_its", "direct", ...)
  std::string message;        ///< why it failed (empty on success)
  std::vector<std::string> warnings;  ///< e.g. PETSc options that were given but never used
  int iterations = 0;         ///< 1 for direct solvers
  Real residual = 0;          ///< true relative residual ||b - A x|| / ||b||
  std::vector<Real> residual_history;  ///< iterative solvers: the residual norm per iteration
  double seconds_setup = 0;   ///< factorisation or preconditioner set-up (part of seconds)
  double seconds = 0;         ///< set-up + solve
};

SolveReport solve(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& options = {});

namespace detail {
class Backend;
}

/// A solver set up once for one matrix and reused for many right-hand sides (implicit time
/// stepping, parameter sweeps): the constructor factorises (direct solvers) or builds the
/// preconditioner (PETSc, BiCGSTAB); solve() then costs a back-substitution or the Krylov
/// iterations only. Keeps its own copy of the matrix. `auto` picks by size as solve() does,
/// without solve()'s fallback to a direct solver (a failed solve is a failed report).
/// Throws like solve(): ConfigError (options), ResourceError (a factorisation beyond the
/// memory limit), NumericalError (a failed factorisation or PETSc set-up).
class PreparedSolver {
 public:
  PreparedSolver(const CsrMatrix& A, const SolverOptions& options = {});
  ~PreparedSolver();
  PreparedSolver(PreparedSolver&&) noexcept;
  PreparedSolver& operator=(PreparedSolver&&) noexcept;
  /// x: on entry the initial guess of iterative solvers (size 0: zero), on exit the solution.
  /// The report's seconds are this solve's; seconds_setup is the one-time set-up.
  SolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  /// Solves A x = b for another matrix A of the same size close to this solver's (the next
  /// time step's, the particles moved a little) without a new set-up: a factorisation
  /// (direct()) preconditions BiCGSTAB, a few of its solves; PETSc on one rank runs its KSP on
  /// A with the preconditioner (the AMG hierarchy) of this matrix (reuses_hierarchy()).
  /// x: initial guess (size 0: zero), then the solution. Not converged within max_iterations:
  /// a failed report, as solve().
  SolveReport solve_nearby(const CsrMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x, Real rtol,
                           int max_iterations) const;
  /// A factorisation (sparselu, umfpack): solve() is two triangular solves.
  bool direct() const { return options_.type == SolverType::SparseLU || options_.type == SolverType::UmfPack; }
  /// PETSc on one rank: solve_nearby() keeps this matrix's preconditioner for the other one.
  bool reuses_hierarchy() const { return options_.type == SolverType::Petsc && !options_.communicator.distributed(); }
  const std::string& solver() const;  ///< what runs: "umfpack", "petsc gmres+hypre(boomeramg)", ...
  double seconds_setup() const;
  Index size() const { return static_cast<Index>(A_->rows()); }

 private:
  // On the heap: the back-end borrows the matrix (its arrays, or the object itself), so it
  // must keep its address when the PreparedSolver is moved.
  std::unique_ptr<const CsrMatrix> A_;
  SolverOptions options_;
  std::unique_ptr<detail::Backend> backend_;
};

}  // namespace vrsph
