// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The pressure Poisson equation of a projection, A p = r, for a matrix over every particle whose
// rows all annihilate constants: the method's Laplacian rows of a fully periodic cloud (and, with
// walls, their Neumann rows). A is then singular, its null space the constants, and r is
// compatible with it only up to truncation. As the periodic boundary value problems do
// (docs/periodic.md): one particle's row is pinned (p = 0) and the defect of the equation that
// pin replaced is spread evenly, so the result satisfies A p = r - λ at every particle, λ one
// constant (the part of r no pressure can balance), and has zero mean. The defect may be spread
// with other weights w instead (A p = r - λ w): with walls, the left null vector y of A, so that
// the part of r removed is the smallest possible one (λ y, y ⊥ range A) and the pressure is the
// pseudo-inverse's; weights of their own (ones over the fluid) amplify λ by 1 / (y·w), which the
// Neumann rows of walls can make large (docs/flow.md, "Walls").
// The pinned matrix is factorised (or its preconditioner built) once, with the unit-source
// solution the spreading needs; every right-hand side after that costs one solve. Rebuild it
// when the matrix changes (particles that move) — or build it "nearby" a previous one: the
// previous factorisation then preconditions BiCGSTAB on the new matrix (a few triangular solves
// instead of a new factorisation; PreparedSolver::solve_nearby).
#include <memory>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

/// The left null vector y of a singular A whose null space is one-dimensional (yᵀ A = 0),
/// scaled to y_pinned = 1: one solve with the transpose of A pinned at `pinned` (a particle
/// where y does not vanish: a fluid particle). NumericalError when that solve fails.
Field left_null_vector(const CsrMatrix& A, const SolverOptions& options, Index pinned);

class PressurePoisson {
 public:
  /// A: N x N (taken by value: its pinned form is made in place), every row summing to zero
  /// (InputError otherwise, naming the row); pinned: the
  /// particle whose row is replaced (any; the result does not depend on it beyond the solver's
  /// tolerance); spread: the weights w of the defect (size 0: all ones; else N finite values).
  /// Throws as PreparedSolver, and NumericalError when the unit source leaves no defect (A's
  /// rows are not a consistent Laplacian).
  PressurePoisson(CsrMatrix A, const SolverOptions& options, Index pinned = 0, Field spread = {});
  /// A non-singular A (Dirichlet rows: a free surface where p = 0): solve() solves A p = r as it
  /// is, with no pin, no shift and no mean removed. Throws as PreparedSolver.
  static PressurePoisson regular(CsrMatrix A, const SolverOptions& options);
  /// The same equation for a new matrix A close to `previous`'s (the next stage of moving
  /// particles), solved by BiCGSTAB preconditioned with previous's factorisation, which is
  /// shared, not copied: A's own is made only if a solve does not converge within
  /// nearby_max_iterations (then every later solve uses it). `previous` must be of the same
  /// kind (regular or pinned) and size and be a factorisation or a PETSc AMG hierarchy
  /// (can_precondition(); PETSc: FGMRES on A with previous's hierarchy, to the solver's rtol).
  static PressurePoisson nearby(CsrMatrix A, const PressurePoisson& previous, const SolverOptions& options,
                                Index pinned = 0, Field spread = {});
  /// A direct solver's set-up: cheap to apply to a nearby matrix's solves (nearby()).
  bool can_precondition() const { return solver_ && (solver_->direct() || solver_->reuses_hierarchy()); }
  /// Solved by PETSc on one rank: nearby() reuses its AMG hierarchy (else, if can_precondition(),
  /// a factorisation).
  bool hierarchy() const { return solver_ && solver_->reuses_hierarchy(); }
  /// The most BiCGSTAB iterations a nearby solve may take before the matrix is factorised (an
  /// AMG hierarchy's: at least this, and twice the hierarchy's own iterations).
  static constexpr int nearby_max_iterations = 30;
  /// The relative residual nearby solves reach (a factorisation's own is about 1e-15).
  static constexpr Real nearby_rtol = 1e-12;
  /// Solves preconditioned by another matrix's factorisation so far (0: factorised itself),
  /// and their BiCGSTAB iterations.
  int nearby_solves() const { return nearby_solves_; }
  int nearby_iterations() const { return nearby_iterations_; }
  /// Whether the next matrix should be solved nearby this one (nearby()): always for a
  /// factorisation (a failed solve sets up its own); an AMG hierarchy while its last solve took
  /// at most hierarchy_growth times the iterations of a solve with its own matrix (the particles
  /// moved away from it; a new hierarchy is then cheaper than the iterations it saves).
  bool worth_reusing() const;
  static constexpr Real hierarchy_growth = 1.1;
  ~PressurePoisson();
  PressurePoisson(PressurePoisson&&) noexcept;
  PressurePoisson& operator=(PressurePoisson&&) noexcept;

  struct Result {
    SolveReport report;  ///< the solve of this right-hand side
    Real shift = 0;      ///< λ: A p = r - λ w at every particle
  };
  /// p: on entry an initial guess for iterative solvers (size 0: none), on exit the solution
  /// with zero mean. NumericalError when the solve fails (the report's message in it).
  Result solve(const Field& r, Field& p) const;
  /// The set-up's report (the factorisation or preconditioner and the unit-source solve).
  const SolveReport& setup() const { return setup_; }
  Index size() const { return n_; }
  bool is_regular() const { return regular_; }

 private:
  PressurePoisson() = default;
  // The set-ups of the pinned and of the regular equation; `previous`: solved nearby it.
  void prepare(CsrMatrix A, Index pinned, Field spread, const PressurePoisson* previous);
  void prepare_regular(CsrMatrix A, const PressurePoisson* previous);
  /// solver_ (and, nearby, matrix_) for the final matrix A: previous's factorisation, or A's own.
  void set_up_solver(CsrMatrix A, const PressurePoisson* previous);
  /// This equation's own set-up time: 0 while it borrows a previous factorisation.
  double own_setup_seconds() const { return matrix_ ? 0.0 : solver_->seconds_setup(); }
  /// One solve of the pinned (or regular) matrix: by its factorisation, or nearby.
  SolveReport run(const Field& b, Field& x) const;
  bool regular_ = false;
  Real pinned_defect(const Field& x, Real rhs) const;
  Index n_ = 0, pinned_ = 0;
  std::vector<std::pair<Index, Real>> row_;  ///< the pinned particle's row of A
  SolverOptions options_;
  /// The factorisation of this matrix, or (nearby, matrix_ set) of a previous one's.
  mutable std::shared_ptr<const PreparedSolver> solver_;
  /// Nearby: the pinned matrix itself, until a solve needs its own factorisation.
  mutable std::shared_ptr<const CsrMatrix> matrix_;
  mutable int nearby_solves_ = 0, nearby_iterations_ = 0;
  mutable int own_iterations_ = 0, last_iterations_ = 0;  // worth_reusing(): the hierarchy's own solves, the last
  Field z_;  ///< the pinned solution for the source w (z_p = 0)
  Real spread_pinned_ = 1;  ///< w at the pinned particle
  Real sigma_ = 0;
  SolveReport setup_;
};

}  // namespace vrsph
