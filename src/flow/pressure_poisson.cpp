// SPDX-License-Identifier: BSD-3-Clause
// The singular pressure Poisson equation, pinned and its defect spread (pressure_poisson.hpp).
#include <algorithm>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/pressure_poisson.hpp>

namespace vrsph {

namespace {
// A's row p replaced by the identity's, and the zeros the methods store (VRSPH keeps its whole
// neighbour pattern, most of it without volume) dropped: less work for the solver.
void pin_row(CsrMatrix& A, Index p) {
  for (CsrMatrix::InnerIterator it(A, p); it; ++it) it.valueRef() = it.col() == p ? 1.0 : 0.0;
  A.prune(0.0);
  A.makeCompressed();
}
}  // namespace

Field left_null_vector(const CsrMatrix& A, const SolverOptions& options, Index pinned) {
  const Index n = static_cast<Index>(A.rows());
  check<InputError>(A.rows() == A.cols() && pinned >= 0 && pinned < n, "left null vector: a square matrix and a pinned "
                    "particle in it");
  // A = A' + e_p (a - e_p)ᵀ with A' pinned at p and a its original row p; yᵀA = 0 with y_p = 1
  // is then A'ᵀ y = -(a - e_p).
  Field rhs = Field::Zero(n);
  for (CsrMatrix::InnerIterator it(A, pinned); it; ++it) rhs[it.col()] = -it.value();
  rhs[pinned] += 1;
  CsrMatrix pinned_matrix = A;
  pin_row(pinned_matrix, pinned);
  const CsrMatrix transposed = pinned_matrix.transpose();
  PreparedSolver solver(transposed, options);
  Field y;
  const SolveReport r = solver.solve(rhs, y);
  check<NumericalError>(r.success && y.allFinite(), "left null vector: the transposed solve failed (", r.solver, ": ",
                        r.message, ")");
  return y;
}

PressurePoisson::PressurePoisson(CsrMatrix A, const SolverOptions& options, Index pinned, Field spread) {
  options_ = options;
  prepare(std::move(A), pinned, std::move(spread), nullptr);
}

void PressurePoisson::prepare(CsrMatrix A, Index pinned, Field spread, const PressurePoisson* previous) {
  n_ = static_cast<Index>(A.rows());
  pinned_ = pinned;
  check<InputError>(A.rows() == A.cols() && n_ > 1, "pressure Poisson: the matrix must be square over at least two "
                    "particles, got ", A.rows(), " x ", A.cols());
  check<InputError>(pinned_ >= 0 && pinned_ < n_, "pressure Poisson: pinned particle ", pinned_, " outside 0..", n_ - 1);
  for (Index i = 0; i < n_; ++i) {
    Real sum = 0, size = 0;
    for (CsrMatrix::InnerIterator it(A, i); it; ++it) {
      check<InputError>(std::isfinite(it.value()), "pressure Poisson: row ", i, " has a non-finite entry");
      sum += it.value();
      size += std::abs(it.value());
      if (i == pinned_) row_.emplace_back(it.col(), it.value());
    }
    // Rows in difference form sum to round-off; anything more is not a Laplacian's row.
    check<InputError>(std::abs(sum) <= 1e-8 * size, "pressure Poisson: row ", i, " sums to ", sum, " (of ", size,
                      "): its rows must annihilate constants (a Laplacian in difference form)");
  }
  if (spread.size() == 0) spread = Field::Ones(n_);
  check<InputError>(spread.size() == n_ && spread.allFinite(), "pressure Poisson: ", spread.size(),
                    " spreading weights for ", n_, " particles (or not finite)");
  pin_row(A, pinned_);  // row_ keeps the original row for the defect
  set_up_solver(std::move(A), previous);
  spread_pinned_ = spread[pinned_];
  Field unit = std::move(spread);
  unit[pinned_] = 0;
  z_.resize(0);
  setup_ = run(unit, z_);
  check<NumericalError>(setup_.success, "pressure Poisson: the unit-source solve failed (", setup_.solver, ": ",
                        setup_.message, "); a direct solver (umfpack) may solve what the iterative one could not");
  setup_.seconds_setup = own_setup_seconds();
  sigma_ = pinned_defect(z_, spread_pinned_);
  check<NumericalError>(std::isfinite(sigma_) && sigma_ != 0, "pressure Poisson: a unit source leaves no defect at the "
                        "pinned particle (sigma = ", sigma_, "); the rows are not a consistent Laplacian");
}

PressurePoisson PressurePoisson::regular(CsrMatrix A, const SolverOptions& options) {
  PressurePoisson p;
  p.options_ = options;
  p.prepare_regular(std::move(A), nullptr);
  return p;
}

void PressurePoisson::prepare_regular(CsrMatrix A, const PressurePoisson* previous) {
  check<InputError>(A.rows() == A.cols() && A.rows() > 0, "pressure Poisson: the matrix must be square, got ", A.rows(),
                    " x ", A.cols());
  check<InputError>(Field(Eigen::Map<const Field>(A.valuePtr(), A.nonZeros())).allFinite(),
                    "pressure Poisson: the matrix has a non-finite entry");
  regular_ = true;
  n_ = static_cast<Index>(A.rows());
  A.prune(0.0);
  A.makeCompressed();
  set_up_solver(std::move(A), previous);
  setup_.seconds_setup = own_setup_seconds();
  setup_.success = true;
}

void PressurePoisson::set_up_solver(CsrMatrix A, const PressurePoisson* previous) {
  if (previous) {
    solver_ = previous->solver_;
    own_iterations_ = previous->own_iterations_;
    matrix_ = std::make_shared<const CsrMatrix>(std::move(A));
  } else {
    solver_ = std::make_shared<const PreparedSolver>(A, options_);
  }
}

PressurePoisson PressurePoisson::nearby(CsrMatrix A, const PressurePoisson& previous, const SolverOptions& options,
                                        Index pinned, Field spread) {
  check<InputError>(previous.can_precondition(), "pressure Poisson: a nearby equation needs a previous one solved by a "
                    "factorisation or a PETSc AMG hierarchy on one rank, got ", previous.solver_ ? previous.solver_->solver() : std::string("none"));
  check<InputError>(A.rows() == previous.n_ && A.cols() == previous.n_, "pressure Poisson: a nearby matrix of ",
                    A.rows(), " x ", A.cols(), " for a previous one over ", previous.n_, " particles");
  PressurePoisson p;
  p.options_ = options;
  if (previous.regular_) p.prepare_regular(std::move(A), &previous);
  else p.prepare(std::move(A), pinned, std::move(spread), &previous);
  return p;
}

bool PressurePoisson::worth_reusing() const {
  return solver_ && (solver_->direct() || (solver_->reuses_hierarchy() && last_iterations_ <= hierarchy_growth * own_iterations_));
}

SolveReport PressurePoisson::run(const Field& b, Field& x) const {
  if (!matrix_) {
    SolveReport own = solver_->solve(b, x);
    own_iterations_ = std::max(own_iterations_, own.iterations);
    last_iterations_ = own.iterations;
    return own;
  }
  const Field guess = x;
  // A factorisation preconditions BiCGSTAB to round-off; an AMG hierarchy keeps the solver's own
  // tolerance (its own matrix's solves stop there too).
  // Its cap: 30 for BiCGSTAB on a factorisation; twice the hierarchy's own iterations for AMG
  // (a harder matrix than the 10-25 its of the flows measured must not fail on the first reuse).
  const Real rtol = solver_->direct() ? nearby_rtol : options_.rtol;
  const int cap = solver_->direct() ? nearby_max_iterations : std::max(nearby_max_iterations, 2 * own_iterations_);
  SolveReport r = solver_->solve_nearby(*matrix_, b, x, rtol, cap);
  ++nearby_solves_;
  nearby_iterations_ += r.iterations;
  last_iterations_ = r.iterations;
  if (r.success) return r;
  // The factorisation of an earlier matrix no longer fits this one: this matrix's own, from
  // now on for every solve.
  solver_ = std::make_shared<const PreparedSolver>(*matrix_, options_);
  matrix_.reset();
  x = guess;
  SolveReport own = solver_->solve(b, x);
  own_iterations_ = last_iterations_ = own.iterations;
  own.seconds_setup = solver_->seconds_setup();
  own.iterations += r.iterations;
  return own;
}

PressurePoisson::~PressurePoisson() = default;
PressurePoisson::PressurePoisson(PressurePoisson&&) noexcept = default;
PressurePoisson& PressurePoisson::operator=(PressurePoisson&&) noexcept = default;

Real PressurePoisson::pinned_defect(const Field& x, Real rhs) const {
  Real s = -rhs;
  for (const auto& [j, w] : row_) s += w * x[j];
  return s;
}

PressurePoisson::Result PressurePoisson::solve(const Field& r, Field& p) const {
  check<InputError>(r.size() == n_, "pressure Poisson: ", r.size(), " right-hand-side values for ", n_, " particles");
  check<InputError>(r.allFinite(), "pressure Poisson: the right-hand side is not finite");
  if (regular_) {
    Result out;
    if (p.size() != n_) p.resize(0);
    out.report = run(r, p);
    check<NumericalError>(out.report.success, "pressure Poisson: the solve failed (", out.report.solver, ": ",
                          out.report.message, ")");
    return out;
  }
  Field b = r;
  b[pinned_] = 0;
  if (p.size() != n_)
    p.resize(0);
  else
    p.array() -= p[pinned_];  // a previous pressure: the pinned solution is zero at the pin
  Result out;
  out.report = run(b, p);
  check<NumericalError>(out.report.success, "pressure Poisson: the solve failed (", out.report.solver, ": ",
                        out.report.message, ")");
  // x1 - (ρ/σ) z meets every equation with r - λ w, λ = ρ/σ (the dropped one included).
  out.shift = pinned_defect(p, r[pinned_]) / sigma_;
  p -= out.shift * z_;
  p.array() -= p.mean();
  return out;
}

}  // namespace vrsph
