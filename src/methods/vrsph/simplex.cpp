// SPDX-License-Identifier: BSD-3-Clause
// Dense two-phase simplex (simplex.hpp).
//
// The tableau holds the variables' columns and the right-hand side only: an artificial
// variable leaves the basis for good, so its column (a column of B^-1) is never needed.
// Artificial variables start basic, one per row. Those of rows with b_i = 0 are held at zero
// (bounded above by 0): a step that would move one off zero is a step of length 0, and it
// leaves the basis on that pivot. Only the rows with b_i != 0 contribute to the phase-1
// objective. On VRSPH's compact rows (b = e_m: every row but Σ μ = 1 homogeneous) this halves
// the pivots of the textbook phase 1, which spent them raising and lowering the zero rows'
// artificial variables; no artificial is left to drive out afterwards but those of rows that
// repeat others.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>
#include <vrsph/methods/vrsph/simplex.hpp>

#include "../../core/compiler_hints.hpp"

// Compiled twice on x86-64 with GCC (AVX2 + FMA, and the baseline; VRSPH_AVX2_CLONES), as the
// NNLS is: the pivot's row updates are the hot loop.

namespace vrsph {

namespace {
// Consecutive degenerate pivots (no change of the objective) after which a phase switches to
// Bland's rule: Dantzig's rule is faster, but on these highly degenerate problems it can cycle.
// Not sooner: Bland's rule is slow to leave a degenerate vertex, and switching after 30
// pivots took the 3D compact rows (35 x ~110) from 61 to 605 pivots a solve in phase 1.
constexpr int kDegenerateRun = 150;
// Relative width within which reduced costs or pivots count as tied (far above round-off, far
// below genuine differences): the first of the tied columns or rows is taken.
constexpr Real kTie = 1e-10;

// basis_ entry of row i's artificial variable.
constexpr int artificial(int row) { return -1 - row; }

// Each row of T (rows 0..rows, width w) except `row`: T_i -= T_i[col] T_row, with T_row
// already divided by its pivot.
VRSPH_AVX2_CLONES void eliminate(Real* T, int rows, std::size_t w, int row, int col) {
  const Real* __restrict pr = T + static_cast<std::size_t>(row) * w;
  for (int i = 0; i <= rows; ++i) {
    if (i == row) continue;
    Real* __restrict ri = T + static_cast<std::size_t>(i) * w;
    const Real f = ri[col];
    if (f == 0) continue;
    for (std::size_t k = 0; k < w; ++k) ri[k] -= f * pr[k];
    ri[col] = 0;
  }
}
}  // namespace

DenseSimplex::DenseSimplex(int max_rows, int max_cols) { reserve(max_rows, max_cols); }

void DenseSimplex::reserve(int m, int n) {
  if (m <= cap_m_ && n <= cap_n_) return;
  cap_m_ = std::max(m, cap_m_);
  cap_n_ = std::max(n, cap_n_);
  const auto M = static_cast<std::size_t>(cap_m_), N = static_cast<std::size_t>(cap_n_);
  T_.resize((M + 1) * (N + 1));
  basis_.resize(M);
  basic_.resize(N);
  held_.resize(M);
  dual_.resize(M * M + M);
}

// Tableau: rows 0..m-1 the constraints, row m the reduced costs of the current phase (its
// right-hand-side entry is minus the objective); columns 0..n-1 the variables, n the
// right-hand side.
void DenseSimplex::pivot(int row, int col) {
  const auto W = static_cast<std::size_t>(width_);
  Real* pr = T_.data() + static_cast<std::size_t>(row) * W;
  const Real inv = 1 / pr[col];
  for (std::size_t k = 0; k < W; ++k) pr[k] *= inv;
  pr[col] = 1;
  eliminate(T_.data(), m_, W, row, col);
  const int leaving = basis_[static_cast<std::size_t>(row)];
  if (leaving >= 0) basic_[static_cast<std::size_t>(leaving)] = 0;
  held_[static_cast<std::size_t>(row)] = 0;
  basis_[static_cast<std::size_t>(row)] = col;
  basic_[static_cast<std::size_t>(col)] = 1;
}

LpStatus DenseSimplex::run_phase(Real* cost, int& iterations, int max_iterations) {
  const auto W = static_cast<std::size_t>(width_);
  const auto rhs = static_cast<std::size_t>(n_);
  bool bland = false;
  int degenerate = 0;
  for (;;) {
    // Dantzig: the most negative reduced cost, and of those within kTie of it the first
    // (symmetric columns of a lattice tie up to round-off, and the round-off must not choose);
    // Bland: the first improving column. A basic column's reduced cost is exactly 0 (pivots
    // keep its unit column exact), so none is ever chosen and the scan needs no test for it:
    // the minimum in four independent lanes (the branchy scan was half of this function).
    int q = -1;
    if (bland) {
      for (int j = 0; j < n_ && q < 0; ++j)
        if (cost[j] < -cost_tol_) q = j;
    } else {
      Real part[4] = {0, 0, 0, 0};
      int j = 0;
      for (; j + 4 <= n_; j += 4)
        for (int l = 0; l < 4; ++l) part[l] = std::min(part[l], cost[j + l]);
      for (; j < n_; ++j) part[0] = std::min(part[0], cost[j]);
      const Real best = std::min(std::min(part[0], part[1]), std::min(part[2], part[3]));
      if (best < -cost_tol_) {
        const Real threshold = best - kTie * best;  // best < 0: a little above it
        for (j = 0; q < 0; ++j)
          if (cost[j] <= threshold) q = j;
      }
    }
    if (q < 0) return LpStatus::Optimal;
    // Ratio test: the largest step that keeps every basic variable >= 0 and every held
    // artificial variable at 0 (a step of 0 wherever its row has an entry of either sign).
    // Among tied rows the held ones first, then the largest pivot (stability), or under
    // Bland's rule the row whose basic variable comes first (artificial variables before all;
    // no cycling). (Computing the ratios first without branches and choosing after was no
    // faster: 0.79-0.92 against 0.73-0.84 s for the compact rows at n = 300, alternately.)
    int r = -1;
    Real ratio = std::numeric_limits<Real>::infinity(), piv = 0;
    for (int i = 0; i < m_; ++i) {
      const Real* ti = T_.data() + static_cast<std::size_t>(i) * W;
      const Real a = ti[q];
      const bool held = held_[static_cast<std::size_t>(i)] != 0;
      const Real size = held ? std::abs(a) : a;
      if (!(size > pivot_tol_)) continue;
      const Real t = held ? 0 : std::max(ti[rhs], Real(0)) / a;
      bool take = r < 0;
      if (!take) {
        const Real tie = 1e-12 * (1 + ratio);
        if (t < ratio - tie)
          take = true;
        else if (t <= ratio + tie)
          take = bland ? basis_[static_cast<std::size_t>(i)] < basis_[static_cast<std::size_t>(r)]
                       : held > (held_[static_cast<std::size_t>(r)] != 0) ||
                             (held == (held_[static_cast<std::size_t>(r)] != 0) && size > piv * (1 + kTie));
      }
      if (take) {
        r = i;
        ratio = std::min(t, ratio);
        piv = size;
      }
    }
    const Real step = ratio;
    if (r < 0) return LpStatus::Unbounded;
    if (++iterations > max_iterations) return LpStatus::IterationLimit;
    degenerate = step == 0 ? degenerate + 1 : 0;
    if (degenerate > kDegenerateRun) bland = true;
    pivot(r, q);
  }
}

// The tableau of A x = b (rows with b_i < 0 negated, so that the artificial basis is
// feasible), every row's artificial variable basic, those of the rows with b_i = 0 held.
Real DenseSimplex::load(const Real* A, int m, int n, const Real* b) {
  check<InputError>(m >= 1 && n >= 0, "simplex: invalid problem size ", m, " x ", n);
  reserve(m, n);
  m_ = m;
  n_ = n;
  width_ = n + 1;
  const auto M = static_cast<std::size_t>(m), N = static_cast<std::size_t>(n), W = static_cast<std::size_t>(width_);
  Real amax = 0, bnorm = 0;
  for (std::size_t i = 0; i < M; ++i) {
    Real* ti = T_.data() + i * W;
    const Real s = b[i] < 0 ? -1 : 1;
    for (std::size_t j = 0; j < N; ++j) {
      ti[j] = s * A[i * N + j];
      amax = std::max(amax, std::abs(ti[j]));
    }
    ti[N] = s * b[i];
    bnorm += std::abs(b[i]);
    basis_[i] = artificial(static_cast<int>(i));
    held_[i] = b[i] == 0;
  }
  std::fill(basic_.begin(), basic_.begin() + static_cast<std::ptrdiff_t>(N), 0);
  amax_ = std::max(amax, std::numeric_limits<Real>::min());
  pivot_tol_ = 1e-9 * amax_;
  return bnorm;
}

// Every artificial variable still basic is at (or within the tolerance of) zero: held there
// from now on, and pivoted out on its row's largest entry where the row has one.
void DenseSimplex::hold_artificials() {
  const auto W = static_cast<std::size_t>(width_);
  for (std::size_t i = 0; i < static_cast<std::size_t>(m_); ++i) {
    if (basis_[i] >= 0) continue;
    held_[i] = 1;
    const Real* ti = T_.data() + i * W;
    int q = -1;
    Real best = pivot_tol_;
    for (int j = 0; j < n_; ++j)
      if (!basic_[static_cast<std::size_t>(j)] && std::abs(ti[j]) > best) {
        best = std::abs(ti[j]);
        q = j;
      }
    if (q >= 0) pivot(static_cast<int>(i), q);
  }
}

// Phase 2 from the current (feasible) basis: reduced costs c_j - c_B^T T_j, then x.
void DenseSimplex::phase_two(const Real* c, Real* x, LpResult& res, int max_iterations) {
  const auto M = static_cast<std::size_t>(m_), N = static_cast<std::size_t>(n_), W = static_cast<std::size_t>(width_);
  Real* cost = T_.data() + M * W;
  Real cmax = 0;
  for (std::size_t j = 0; j < N; ++j) cmax = std::max(cmax, std::abs(c[j]));
  for (std::size_t j = 0; j < N; ++j) cost[j] = c[j];
  cost[N] = 0;
  for (std::size_t i = 0; i < M; ++i) {
    const int bj = basis_[i];
    if (bj < 0) continue;  // an artificial variable at zero: cost 0
    const Real cb = c[bj];
    if (cb == 0) continue;
    const Real* ti = T_.data() + i * W;
    for (std::size_t j = 0; j <= N; ++j) cost[j] -= cb * ti[j];
  }
  cost_tol_ = 1e-11 * std::max(cmax, std::numeric_limits<Real>::min()) * static_cast<Real>(m_);
  res.status = run_phase(cost, res.iterations, max_iterations);
  if (res.status != LpStatus::Optimal) return;
  for (std::size_t i = 0; i < M; ++i) {
    const int bj = basis_[i];
    if (bj < 0) continue;
    const Real v = std::max(T_[i * W + N], Real(0));
    x[bj] = v;
    res.objective += c[bj] * v;
    res.positive += v > 0 ? 1 : 0;
  }
}

LpResult DenseSimplex::solve(const Real* A, int m, int n, const Real* b, const Real* c, Real* x,
                             const LpOptions& options) {
  const Real bnorm = load(A, m, n, b);
  const auto M = static_cast<std::size_t>(m), W = static_cast<std::size_t>(width_), N = static_cast<std::size_t>(n);
  std::fill(x, x + n, 0.0);
  LpResult res;
  const int max_it = options.max_iterations >= 0 ? options.max_iterations : 10 * (m + n);

  // Phase 1: minimise the artificial variables of the rows with b_i != 0; reduced costs
  // -Σ_i T[i][j] over those rows.
  Real* cost = T_.data() + M * W;
  std::fill(cost, cost + W, 0.0);
  for (std::size_t i = 0; i < M; ++i) {
    if (held_[i]) continue;
    const Real* ti = T_.data() + i * W;
    for (std::size_t j = 0; j <= N; ++j) cost[j] -= ti[j];
  }
  cost_tol_ = 1e-11 * amax_ * static_cast<Real>(m);
  const int phase1_max = options.phase1_iterations >= 0 ? std::min(max_it, options.phase1_iterations) : max_it;
  res.status = run_phase(cost, res.iterations, phase1_max);
  if (res.status == LpStatus::IterationLimit) return res;
  // Σ of the artificial variables left (those held are at zero).
  Real infeasibility = 0;
  for (std::size_t i = 0; i < M; ++i)
    if (basis_[i] < 0 && !held_[i]) infeasibility += std::max(T_[i * W + N], Real(0));
  if (!(infeasibility <= options.feasibility * std::max(bnorm, Real(1)))) {
    res.status = LpStatus::Infeasible;
    res.residual_bound = farkas_bound(A, b, options.bound_x_sum);
    return res;
  }
  hold_artificials();
  phase_two(c, x, res, max_it);
  return res;
}

LpResult DenseSimplex::solve_from(const Real* A, int m, int n, const Real* b, const Real* c, const Real* start,
                                  Real* x, const LpOptions& options) {
  const Real bnorm = load(A, m, n, b);
  const auto M = static_cast<std::size_t>(m), W = static_cast<std::size_t>(width_), N = static_cast<std::size_t>(n);
  std::fill(x, x + n, 0.0);
  LpResult res;
  const int max_it = options.max_iterations >= 0 ? options.max_iterations : 10 * (m + n);
  // The start's positive columns into the basis, each on the row (still an artificial
  // variable's) where its entry is largest: Gaussian elimination with partial pivoting of
  // those columns. A column dependent on those before it finds no row and stays out.
  for (std::size_t j = 0; j < N; ++j) {
    if (!(start[j] > 0)) continue;
    int r = -1;
    Real best = pivot_tol_;
    for (std::size_t i = 0; i < M; ++i)
      if (basis_[i] < 0 && std::abs(T_[i * W + j]) > best) {
        best = std::abs(T_[i * W + j]);
        r = static_cast<int>(i);
      }
    if (r >= 0) pivot(r, static_cast<int>(j));
  }
  // The basis is feasible when its structural variables are >= 0 and its artificial ones 0,
  // each to the tolerance of phase 1's end (then set to exactly that).
  const Real tol = options.feasibility * std::max(bnorm, Real(1));
  for (std::size_t i = 0; i < M; ++i) {
    Real& rhs = T_[i * W + N];
    if (basis_[i] >= 0 ? rhs < -tol : std::abs(rhs) > tol) {
      res.status = LpStatus::Infeasible;
      return res;
    }
    if (rhs < 0 || basis_[i] < 0) rhs = 0;
  }
  hold_artificials();
  phase_two(c, x, res, max_it);
  return res;
}

// Phase 1 minimised the artificial variables of the rows with b_i != 0 over S A x + a = S b
// (S the rows' signs), and its optimum is positive. Its dual y (B^T y = c_B, c_B 1 at those
// rows' basic artificial variables, else 0) is then a Farkas certificate: the reduced costs
// -(S A)^T y are >= 0 at the optimum and (S b)^T y is the optimum. For x >= 0,
// y^T S (b - A x) >= (S b)^T y - max_j z_j^+ sum x with z = (S A)^T y (z <= 0 but for round-off),
// so ||A x - b|| is at least that over ||y||. Solved afresh from the final basis (the tableau
// keeps no columns of B^-1): an m x m LU, a few microseconds, where a caller's confirming
// search costs tens.
Real DenseSimplex::farkas_bound(const Real* A, const Real* b, Real x_sum) {
  const auto M = static_cast<std::size_t>(m_), N = static_cast<std::size_t>(n_);
  Real* Bt = dual_.data();  // B^T column-major: its column k is row k of B (B's columns the basic ones)
  Real* y = dual_.data() + M * M;
  for (std::size_t r = 0; r < M; ++r) {
    const int j = basis_[r];
    for (std::size_t k = 0; k < M; ++k)
      Bt[k * M + r] = j >= 0 ? (b[k] < 0 ? -1 : 1) * A[k * N + static_cast<std::size_t>(j)] : Real(k == r ? 1 : 0);
    y[r] = j < 0 && b[r] != 0 ? 1 : 0;
  }
  if (!solve_square_positive(Bt, m_, y, -std::numeric_limits<Real>::infinity())) return 0;
  // y in the original rows' signs: (S b)^T y = b^T (S y), (S A)^T y = A^T (S y).
  Real by = 0, yy = 0;
  for (std::size_t i = 0; i < M; ++i) {
    if (b[i] < 0) y[i] = -y[i];
    by += b[i] * y[i];
    yy += y[i] * y[i];
  }
  Real zmax = 0;
  for (std::size_t j = 0; j < N; ++j) {
    Real z = 0;
    for (std::size_t i = 0; i < M; ++i) z += A[i * N + j] * y[i];
    zmax = std::max(zmax, z);
  }
  const Real bound = (by - zmax * x_sum) / std::sqrt(yy);
  return std::isfinite(bound) && bound > 0 ? bound : 0;
}

}  // namespace vrsph
