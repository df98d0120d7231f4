// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A dense two-phase simplex method for the many small linear programs
//   min c^T x  subject to  A x = b,  x >= 0
// that VRSPH's compact rows pose (rows 15 in 2D, 35 in 3D; columns 2 x neighbours + 2).
// Among the (many) non-negative solutions of a row's moment conditions it picks the one whose
// bound on the next degree's truncation error, a weighted l1 norm c^T x, is least; the
// Lawson–Hanson NNLS, which finds *a* solution, leaves that choice to its path.
//
// Written by hand for the same reason as NnlsSolver: every particle solves one, and a general
// LP library (GLPK) costs tens of microseconds a problem in set-up alone. The tableau
// ((m + 1) x (n + 1): no columns for the artificial variables, which never re-enter) fits in
// the L1 cache at these sizes; Dantzig's rule with the largest pivot among tied ratios, and
// Bland's rule after a run of degenerate pivots (b is zero but for one entry, so degeneracy is
// the rule, and Bland's rule cannot cycle). No heap allocation per solve.
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

enum class LpStatus { Optimal, Infeasible, Unbounded, IterationLimit };

struct LpOptions {
  /// Phase 1 ends infeasible when the artificial variables still sum to more than this
  /// (|b|_1 times it). The caller checks the residual of the answer in its own norm.
  Real feasibility = 1e-10;
  int max_iterations = -1;  ///< pivots over both phases; < 0: 10 (m + n)
  /// Pivots of phase 1 at most (< 0: max_iterations): on highly degenerate problems phase 1
  /// can wander for thousands of pivots where a caller finds a feasible point sooner by other
  /// means (an NNLS) and goes on with solve_from.
  int phase1_iterations = -1;
  /// Infeasible: LpResult::residual_bound holds for every x >= 0 whose entries sum to at most
  /// this (the certificate's round-off is weighed against it).
  Real bound_x_sum = 1e6;
};

struct LpResult {
  LpStatus status = LpStatus::Optimal;
  int iterations = 0;  ///< pivots over both phases
  Real objective = 0;  ///< c^T x of the returned x (Optimal)
  int positive = 0;    ///< entries of x above zero
  /// Infeasible: a lower bound on ||A x - b||_2 over x >= 0 (with sum x <= LpOptions::
  /// bound_x_sum), from phase 1's dual (a Farkas certificate y: A^T y <= 0, b^T y > 0, so
  /// ||A x - b|| >= b^T y / ||y|| for every such x); 0 where the certificate does not hold
  /// up. A caller that accepts an x by its residual can skip its own search where this bound
  /// already exceeds its tolerance.
  Real residual_bound = 0;
};

class DenseSimplex {
 public:
  /// Workspace for problems up to max_rows x max_cols (grown on demand, never shrunk).
  DenseSimplex(int max_rows = 16, int max_cols = 64);
  /// A: m x n row-major (row i = A + i n); b: m values; c: n values; x receives n values (the
  /// optimal vertex when Optimal, zeros otherwise). Columns whose entries are all zero are
  /// fine; rows that repeat others (rank-deficient A) are left basic on their artificial at zero.
  LpResult solve(const Real* A, int m, int n, const Real* b, const Real* c, Real* x, const LpOptions& options = {});
  /// Phase 2 alone, from a start x0 >= 0: the columns of its positive entries make the first
  /// basis (of those that are dependent on the ones before them, none) and phase 2 goes on
  /// from that basic solution — x0 itself where x0 is a vertex with A x0 = b, such as an NNLS
  /// answer of zero residual. Infeasible when that basic solution is not feasible (a variable
  /// below -LpOptions::feasibility |b|_1, or a row it leaves unsatisfied by more).
  LpResult solve_from(const Real* A, int m, int n, const Real* b, const Real* c, const Real* x0, Real* x,
                      const LpOptions& options = {});

 private:
  void reserve(int m, int n);
  void pivot(int row, int col);
  // One phase: entering columns by the reduced costs in `cost` (the tableau's objective row)
  // until optimal; the iteration limit or an unbounded direction end it early.
  LpStatus run_phase(Real* cost, int& iterations, int max_iterations);
  Real load(const Real* A, int m, int n, const Real* b);  // the tableau; returns |b|_1
  void hold_artificials();
  void phase_two(const Real* c, Real* x, LpResult& res, int max_iterations);
  // After phase 1 ended infeasible: LpResult::residual_bound from its dual y (B^T y = c_B).
  Real farkas_bound(const Real* A, const Real* b, Real x_sum);

  std::vector<Real> T_;      ///< tableau, (m + 1) x (n + 1) row-major: constraints, then the reduced costs
  std::vector<int> basis_;   ///< per constraint row: its basic column (< 0: the row's artificial variable)
  std::vector<char> basic_;  ///< per column: 1 = basic
  std::vector<char> held_;   ///< per row: its basic variable is an artificial one held at zero
  std::vector<Real> dual_;   ///< farkas_bound's m x m system and its solution
  int m_ = 0, n_ = 0, width_ = 0;
  int cap_m_ = 0, cap_n_ = 0;
  Real pivot_tol_ = 1e-9, cost_tol_ = 0, amax_ = 1;
};

}  // namespace vrsph
