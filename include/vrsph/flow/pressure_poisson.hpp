// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The pressure Poisson equation of a projection, A p = r, for a matrix over every particle whose
// rows all annihilate constants: the method's Laplacian rows of a fully periodic cloud (and, with
// walls, their Neumann rows). A is then singular, its null space the constants, and r is
// compatible with it only up to truncation. As the periodic boundary value problems do
// (docs/periodic.md): one particle's row is pinned (p = 0) and the defect of the equation that
// pin replaced is spread evenly, so the result satisfies A p = r - λ at every particle, λ one
// constant (the part of r no pressure can balance), and has zero mean.
// The pinned matrix is factorised (or its preconditioner built) once, with the unit-source
// solution the spreading needs; every right-hand side after that costs one solve. Rebuild it
// when the matrix changes (particles that move).
#include <memory>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

class PressurePoisson {
 public:
  /// A: N x N (taken by value: its pinned form is made in place), every row summing to zero
  /// (InputError otherwise, naming the row); pinned: the
  /// particle whose row is replaced (any; the result does not depend on it beyond the solver's
  /// tolerance). Throws as PreparedSolver, and NumericalError when the unit source leaves no
  /// defect (A's rows are not a consistent Laplacian).
  PressurePoisson(CsrMatrix A, const SolverOptions& options, Index pinned = 0);
  ~PressurePoisson();
  PressurePoisson(PressurePoisson&&) noexcept;
  PressurePoisson& operator=(PressurePoisson&&) noexcept;

  struct Result {
    SolveReport report;  ///< the solve of this right-hand side
    Real shift = 0;      ///< λ: A p = r - λ at every particle
  };
  /// p: on entry an initial guess for iterative solvers (size 0: none), on exit the solution
  /// with zero mean. NumericalError when the solve fails (the report's message in it).
  Result solve(const Field& r, Field& p) const;
  /// The set-up's report (the factorisation or preconditioner and the unit-source solve).
  const SolveReport& setup() const { return setup_; }
  Index size() const { return n_; }

 private:
  Real pinned_defect(const Field& x, Real rhs) const;
  Index n_ = 0, pinned_ = 0;
  std::vector<std::pair<Index, Real>> row_;  ///< the pinned particle's row of A
  std::unique_ptr<PreparedSolver> solver_;
  Field z_;  ///< the pinned solution for a unit source (z_p = 0)
  Real sigma_ = 0;
  SolveReport setup_;
};

}  // namespace vrsph
