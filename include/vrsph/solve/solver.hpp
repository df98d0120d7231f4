#pragma once
// Sparse linear solvers for assembled systems. Non-convergence is a returned status
// (SolveReport::success), never an exception; callers decide (the studies turn a
// failed solve into a NumericalError, never a silent result).
//
// How to choose: sparselu (Eigen, default) is robust for the non-symmetric matrices of
// corrected methods up to ~10^5 unknowns in 2D; umfpack (SuiteSparse) is the faster
// direct solver for large 2D/3D systems; bicgstab (+ incomplete LUT) uses the least
// memory and suits 10^6 unknowns when -L is an M-matrix (VRSPH, SPH).
#include <string>
#include <vrsph/assembly/assemble.hpp>

namespace vrsph {

enum class SolverType { SparseLU, UmfPack, BiCGSTAB };
/// "sparselu" | "umfpack" | "bicgstab"; throws ConfigError otherwise.
SolverType parse_solver(const std::string& name);
std::string to_string(SolverType t);

struct SolverOptions {
  SolverType type = SolverType::SparseLU;
  Real rtol = 1e-10;          ///< iterative: relative residual target
  int max_iterations = 20000; ///< iterative
  Real ilut_drop = 1e-5;      ///< incomplete LUT drop tolerance
  int ilut_fill = 20;         ///< incomplete LUT fill factor
  /// Dimension of the problem's geometry, for the fill-in estimate of the direct solvers
  /// (0: inferred from the nonzeros per row).
  int dimension = 0;
};

/// Memory a sparse LU factorisation (SparseLU/COLAMD or UMFPACK) of A is expected to
/// need, in bytes: c nnz(A) N^((d-1)/d), the nested-dissection growth of the fill-in,
/// with c fitted to peak-memory measurements of both solvers on our matrices (2D:
/// N = 40k and 160k; 3D: N = 24k and 59k; within a factor 2 above the measurements).
double direct_solver_bytes(const CsrMatrix& A, int dimension);

struct SolveReport {
  bool success = false;
  std::string solver;
  std::string message;        ///< why it failed (empty on success)
  int iterations = 0;         ///< 1 for direct solvers
  Real residual = 0;          ///< true relative residual ||b - A x|| / ||b||
  double seconds = 0;
};

SolveReport solve(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& options = {});

}  // namespace vrsph
