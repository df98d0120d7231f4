// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Non-negative least squares, min ||A x - b||_2 subject to x >= 0, for the many small
// dense problems VRSPH poses (rows 3/12/30, columns = neighbours, 10–200).
//
// NnlsSolver is the Lawson–Hanson active-set algorithm (the algorithm of MATLAB's
// lsqnonneg and SciPy's nnls) written for throughput: one workspace per thread, no
// heap allocation per solve, and the thin QR factorisation of the passive columns is
// updated instead of recomputed: classical Gram–Schmidt (second pass by the DGKS test) when a column
// enters, Givens rotations when one leaves. Written by hand because it is our core (every VRSPH particle solves
// one) and no Debian library offers a small-problem NNLS without per-call allocation.
//
// Tolerance (METHODS §3.0): tol = 10 eps ||A||_1 max(m, n), unless given, for the
// multiplier test w_j > tol. Deviation from lsqnonneg: a variable leaves the passive set
// when |x_j| < tol / ||A||_1^2 (not tol), the threshold of the same algorithm run on the
// equivalent problem scaled to ||A||_1 = 1; lsqnonneg's literal rule discarded genuine
// VRSPH volumes at fine resolution (||A||_1 ~ h^-3 against volumes ~ dx^d) and cycled.
// Safeguards (Lawson & Hanson 1974, ch. 23): a column that is numerically dependent
// on the passive set, or whose trial coefficient is not positive, is not admitted.
#include <span>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct NnlsOptions {
  Real tolerance = -1;      ///< multiplier tolerance; < 0: 10 eps ||A||_1 max(m, n)
  int max_iterations = -1;  ///< < 0: 3 n (counts inner and outer iterations)
  /// Relative tie width of the entering column: the first column whose multiplier is within
  /// tie_tolerance |max| of the largest enters (0: the first holding the largest exactly).
  /// Symmetric configurations (a lattice) give multipliers equal up to round-off, and which
  /// of them round-off makes the largest changes with the last bits of the coordinates (the
  /// length unit); a width far above round-off makes the path, so the result, reproducible.
  Real tie_tolerance = 0;
};

enum class NnlsStatus { Converged, IterationLimit };
enum class MatrixOrder { ColumnMajor, RowMajor };

struct NnlsResult {
  NnlsStatus status = NnlsStatus::Converged;
  int iterations = 0;
  int passive = 0;          ///< number of positive entries of x
  Real residual = 0;        ///< ||A x - b||_2
  /// Warm start: columns of the initial passive set kept (their least-squares values positive);
  /// the start was right when warm_kept is the set's size and iterations is 0.
  int warm_kept = 0;
};

class NnlsSolver {
 public:
  /// Workspace for problems up to max_rows x max_cols (grown on demand, never shrunk).
  NnlsSolver(int max_rows = 30, int max_cols = 256);
  /// A is m x n, column-major (column j = A + j*m) or row-major (row i = A + i*n, what the
  /// solver works on: no copy); x receives n values.
  NnlsResult solve(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options = {},
                   MatrixOrder order = MatrixOrder::ColumnMajor);
  /// The same from a guessed passive set (warm start, e.g. the columns a moved particle used at
  /// the previous time step): its columns enter first (dependent or repeated ones are skipped),
  /// those whose least-squares values are not positive leave until the rest are (each solve
  /// on a smaller set), and Lawson–Hanson goes on from that feasible point. The answer is an
  /// optimum like the cold start's; where the optimum is not unique (VRSPH's moment systems
  /// have many optimal vertices) it may be another one. Columns out of [0, n) are ignored.
  NnlsResult solve(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options,
                   MatrixOrder order, std::span<const int> initial_passive);

 private:
  void reserve(int m, int n);
  template <int FixedRows>
  NnlsResult solve_impl(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options,
                        MatrixOrder order, std::span<const int> initial_passive);
  std::vector<Real> Q_, R_, qtb_, z_, w_, r_, xp_, Rinv_, at_, gs_, proj_;  // at_: A row-major (m x n)
  std::vector<int> passive_;  // column index per passive position
  std::vector<char> in_passive_;
  int cap_m_ = 0, cap_n_ = 0;
};

/// The square system S z = b (S column-major m x m, overwritten by its LU factors; z holds b on
/// entry) by LU with partial pivoting. True when S is not (nearly) singular and every z_j >
/// xtol: then z is an NNLS optimum of any problem whose columns include S's (residual zero).
/// The warm start's fast path (a guessed passive set of m columns). With xtol = -infinity a
/// plain solve (false only for a (nearly) singular S or a non-finite z): DenseSimplex's dual.
bool solve_square_positive(Real* S, int m, Real* z, Real xtol);
/// The value threshold below which NnlsSolver drops a variable (m x n problem, ||A||_1 given,
/// default tolerance).
Real nnls_value_tolerance(Real a_norm1, int m, int n);

/// Textbook Lawson–Hanson (a direct transcription of lsqnonneg with a fresh QR of the
/// passive columns at every step and Eigen's dynamic matrices). The reference for
/// tests and the baseline for `vrsph bench volumes`.
NnlsResult nnls_reference(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                          const NnlsOptions& options = {});

}  // namespace vrsph
