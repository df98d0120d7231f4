// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Y = A^-1 R for the small symmetric positive definite systems of the rows exact on polynomials
// (cubic_rows.hpp), with their conditioning test. Private to the library.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vrsph/core/types.hpp>
#include "../core/compiler_hints.hpp"

namespace vrsph::cubic_rows {

// Every loop of the solve unrolled up to 10 trips: the 9 x 9 systems of the 2D cubic rows
// become straight-line code the compiler schedules across the Cholesky's sqrt and division
// chains, 1.5 times faster a solve (395 -> 255 ns, the same bits); M = 14, 19 and 34 gain 0-7 %.
// (Unrolled up to 16 trips, M = 14 was 9 % slower: twice the code for no gain.) GCC only, as
// the warm start's LU (nnls.cpp): clang's builds are the sanitizer and fuzz ones
// (VRSPH_UNROLL_SMALL, core/compiler_hints.hpp).

// Y = A^-1 R (the first `comps` columns) for the symmetric positive definite A (its lower
// triangle read), through its symmetric equilibration B = D A D (unit diagonal: the monomials'
// scales differ by h^-1 ... h^-3 and the test should see geometry, not units) and a Cholesky
// factor B = L L^T written out for the fixed size (Eigen's LLT and rcond ran generic
// triangular-solve kernels that took about half the time of these rows, perf). False when A is
// not positive definite or B's 1-norm condition number exceeds max_condition.
//
// The test needs ||B^-1||_1. Forming B^-1 = L^-T L^-1 was a third of these rows' time on moving
// particles (perf), and nearly every row passes the test by a wide margin, so it is first bounded
// from above: ||B^-1||_1 <= ||L^-1||_inf ||L^-1||_1, and |L^-1| <= M(L)^-1 entrywise for the
// comparison matrix M(L) (|l_ii| on the diagonal, -|l_ij| off it; Higham, Accuracy and Stability
// of Numerical Algorithms, 2nd ed., Thm. 8.12), so each norm is at most the largest entry of one
// triangular solve with M(L) (or its transpose) and a vector of ones. A row whose bound passes
// would pass the exact test; only the others form B^-1: the same rows are kept as with the exact
// test alone (to rounding at the threshold itself).
template <int M, int C>
bool equilibrated_spd_solve(const Eigen::Matrix<Real, M, M>& A, const Eigen::Matrix<Real, M, C>& R, Eigen::Index comps,
                            Eigen::Matrix<Real, M, C>& Y, Real max_condition) {
  constexpr auto m = static_cast<std::size_t>(M);
  std::array<Real, m> scale{};
  VRSPH_UNROLL_SMALL
  for (std::size_t a = 0; a < m; ++a) {
    const Real d = A(static_cast<int>(a), static_cast<int>(a));
    if (!(d > 0) || !std::isfinite(d)) return false;
    scale[a] = 1 / std::sqrt(d);
  }
  // L (lower, row-major in a plain array) and 1 / L_jj: divisions are products with these.
  std::array<Real, m * m> L;  // its lower triangle is all that is written and read
  std::array<Real, m> inv_diag{};
  VRSPH_UNROLL_SMALL
  for (std::size_t j = 0; j < m; ++j) {
    Real d = 1;  // the equilibrated diagonal
    VRSPH_UNROLL_SMALL
    for (std::size_t k = 0; k < j; ++k) d -= L[j * m + k] * L[j * m + k];
    if (!(d > 0)) return false;
    const Real ljj = std::sqrt(d);
    L[j * m + j] = ljj;
    inv_diag[j] = 1 / ljj;
    VRSPH_UNROLL_SMALL
    for (std::size_t i = j + 1; i < m; ++i) {
      Real v = A(static_cast<int>(i), static_cast<int>(j)) * scale[i] * scale[j];
      VRSPH_UNROLL_SMALL
      for (std::size_t k = 0; k < j; ++k) v -= L[i * m + k] * L[j * m + k];
      L[i * m + j] = v * inv_diag[j];
    }
  }
  Real norm = 0;  // ||B||_1
  VRSPH_UNROLL_SMALL
  for (int c = 0; c < M; ++c) {
    Real col = 0;
    VRSPH_UNROLL_SMALL
    for (int i = 0; i < M; ++i)
      col += std::abs(i >= c ? A(i, c) : A(c, i)) * scale[static_cast<std::size_t>(i)] * scale[static_cast<std::size_t>(c)];
    norm = std::max(norm, col);
  }
  // M(L) x = 1 (forward) and M(L)^T y = 1 (backward): every term is non-negative. The
  // triangular solves here and below go column by column (axpy form): an unknown is final once
  // its own column is reached, and the updates it then makes are independent of each other. In
  // the dot-product form each unknown waited for a chain of sums over the ones before it (the
  // backward solves were a third of this function's time, perf).
  std::array<Real, m> x, y;
  x.fill(1);
  y.fill(1);
  VRSPH_UNROLL_SMALL
  for (std::size_t k = 0; k < m; ++k) {
    x[k] *= inv_diag[k];
    VRSPH_UNROLL_SMALL
    for (std::size_t i = k + 1; i < m; ++i) x[i] += std::abs(L[i * m + k]) * x[k];
  }
  VRSPH_UNROLL_SMALL
  for (std::size_t back = 0; back < m; ++back) {
    const std::size_t k = m - 1 - back;
    y[k] *= inv_diag[k];
    VRSPH_UNROLL_SMALL
    for (std::size_t i = 0; i < k; ++i) y[i] += std::abs(L[k * m + i]) * y[k];
  }
  const Real row_bound = *std::max_element(x.begin(), x.end()), col_bound = *std::max_element(y.begin(), y.end());
  if (!(norm * row_bound * col_bound <= max_condition)) {
    // The exact ||B^-1||_1: L^-1 by forward substitution, then B^-1 = L^-T L^-1 on its lower
    // triangle, (B^-1)_ij = Σ_{k >= max(i, j)} Li_ki Li_kj.
    std::array<Real, m * m> Li{};
    VRSPH_UNROLL_SMALL
    for (std::size_t c = 0; c < m; ++c) {
      Li[c * m + c] = inv_diag[c];
      VRSPH_UNROLL_SMALL
      for (std::size_t i = c + 1; i < m; ++i) {
        Real v = 0;
        VRSPH_UNROLL_SMALL
        for (std::size_t k = c; k < i; ++k) v -= L[i * m + k] * Li[k * m + c];
        Li[i * m + c] = v * inv_diag[i];
      }
    }
    std::array<Real, m> col_sum{};
    VRSPH_UNROLL_SMALL
    for (std::size_t j = 0; j < m; ++j)
      VRSPH_UNROLL_SMALL
      for (std::size_t i = j; i < m; ++i) {
        Real v = 0;
        VRSPH_UNROLL_SMALL
        for (std::size_t k = i; k < m; ++k) v += Li[k * m + i] * Li[k * m + j];
        col_sum[j] += std::abs(v);
        if (i != j) col_sum[i] += std::abs(v);
      }
    if (!(norm * *std::max_element(col_sum.begin(), col_sum.end()) <= max_condition)) return false;
  }
  // Y = D L^-T L^-1 D R, the columns side by side.
  const auto nc = static_cast<std::size_t>(comps);
  std::array<std::array<Real, m>, static_cast<std::size_t>(C)> z;
  VRSPH_UNROLL_SMALL
  for (std::size_t c = 0; c < nc; ++c)
    VRSPH_UNROLL_SMALL
    for (std::size_t i = 0; i < m; ++i) z[c][i] = R(static_cast<int>(i), static_cast<Eigen::Index>(c)) * scale[i];
  VRSPH_UNROLL_SMALL
  for (std::size_t k = 0; k < m; ++k)
    VRSPH_UNROLL_SMALL
    for (std::size_t c = 0; c < nc; ++c) {
      z[c][k] *= inv_diag[k];
      VRSPH_UNROLL_SMALL
      for (std::size_t i = k + 1; i < m; ++i) z[c][i] -= L[i * m + k] * z[c][k];
    }
  VRSPH_UNROLL_SMALL
  for (std::size_t back = 0; back < m; ++back)
    VRSPH_UNROLL_SMALL
    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t k = m - 1 - back;
      z[c][k] *= inv_diag[k];
      VRSPH_UNROLL_SMALL
      for (std::size_t i = 0; i < k; ++i) z[c][i] -= L[k * m + i] * z[c][k];
    }
  VRSPH_UNROLL_SMALL
  for (std::size_t c = 0; c < nc; ++c)
    VRSPH_UNROLL_SMALL
    for (std::size_t i = 0; i < m; ++i) Y(static_cast<int>(i), static_cast<Eigen::Index>(c)) = z[c][i] * scale[i];
  return true;
}

}  // namespace vrsph::cubic_rows

