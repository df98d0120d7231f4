// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <vrsph/methods/vrsph/signed_volumes.hpp>

namespace vrsph {

namespace {
// Weight of the negative part against the fit of the equilibrated system (unit columns,
// rows scaled to max |entry| = 1): small enough that the fit comes first (the correction
// below removes what is left), large enough that NNLS keeps the p and q columns of a
// neighbour apart (they differ only in the penalty row).
constexpr Real kPenalty = 1e-2;
// Columns (equilibrated rows) shorter than this relative to the longest are round-off.
constexpr Real kDeadColumn = 1e-10;
}  // namespace

SignedVolumesResult SignedVolumeSolver::solve(const Real* A, int m, int n, const Real* b, Real* v) {
  const auto um = static_cast<std::size_t>(m), un = static_cast<std::size_t>(n);
  row_scale_.assign(um, 1.0);
  col_scale_.assign(un, 0.0);
  for (std::size_t r = 0; r < um; ++r) {
    Real big = 0;
    for (std::size_t j = 0; j < un; ++j) big = std::max(big, std::abs(A[r * un + j]));
    if (big > 0) row_scale_[r] = 1 / big;
  }
  Real widest = 0;
  for (std::size_t j = 0; j < un; ++j) {
    Real s = 0;
    for (std::size_t r = 0; r < um; ++r) s += std::pow(A[r * un + j] * row_scale_[r], 2);
    col_scale_[j] = std::sqrt(s);
    widest = std::max(widest, col_scale_[j]);
  }
  // A neighbour at the edge of the support has a kernel weight of round-off size (W' -> 0 at
  // r = h): equilibrating its column would make it as strong as any other and give it a
  // volume of 1e28 that only that round-off balances (issue 30: rows exact to 1e-16 on their
  // moment matrix and wrong by O(1) on the monomials). Such columns carry no information: left
  // out (v_j = 0).
  dead_.assign(un, 0);
  for (std::size_t j = 0; j < un; ++j)
    if (!(col_scale_[j] > kDeadColumn * widest)) {
      dead_[j] = 1;
      col_scale_[j] = 1;
    }
  // M = [Ã -Ã; 0 μI] ((m + n) x 2n, row-major), c = [R b; 0].
  const std::size_t rows = um + un, cols = 2 * un;
  M_.assign(rows * cols, 0.0);
  c_.assign(rows, 0.0);
  At_.assign(um * un, 0.0);
  for (std::size_t r = 0; r < um; ++r) {
    c_[r] = row_scale_[r] * b[r];
    for (std::size_t j = 0; j < un; ++j) {
      const Real a = dead_[j] ? 0.0 : A[r * un + j] * row_scale_[r] / col_scale_[j];
      At_[r * un + j] = a;
      M_[r * cols + j] = a;
      M_[r * cols + un + j] = -a;
    }
  }
  for (std::size_t k = 0; k < un; ++k) M_[(um + k) * cols + un + k] = kPenalty;
  z_.assign(cols, 0.0);
  nnls_.solve(M_.data(), static_cast<int>(rows), static_cast<int>(cols), c_.data(), z_.data(), {}, MatrixOrder::RowMajor);

  Eigen::VectorXd x(n);
  for (std::size_t j = 0; j < un; ++j) x[static_cast<Eigen::Index>(j)] = z_[j] - z_[un + j];
  const Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> At(At_.data(), m, n);
  const Eigen::Map<const Eigen::VectorXd> bt(c_.data(), m);
  // The penalty leaves a residual of order μ²: remove it by the minimum-norm correction on the
  // support NNLS chose (so no new, tiny negative volumes appear), or on every column when
  // the support alone cannot (it spans fewer than m directions).
  const Eigen::VectorXd r = bt - At * x;
  std::vector<Eigen::Index> support;
  for (Eigen::Index j = 0; j < n; ++j)
    if (x[j] != 0) support.push_back(j);
  const auto correct = [&](const std::vector<Eigen::Index>& cols_used) {
    Eigen::MatrixXd As(m, static_cast<Eigen::Index>(cols_used.size()));
    for (std::size_t k = 0; k < cols_used.size(); ++k) As.col(static_cast<Eigen::Index>(k)) = At.col(cols_used[k]);
    const Eigen::VectorXd d = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(As).solve(r);
    if ((As * d - r).norm() > 1e-3 * r.norm()) return false;
    for (std::size_t k = 0; k < cols_used.size(); ++k) x[cols_used[k]] += d[static_cast<Eigen::Index>(k)];
    return true;
  };
  if (r.norm() > 0 && !correct(support)) {
    std::vector<Eigen::Index> all(un);
    for (std::size_t j = 0; j < un; ++j) all[j] = static_cast<Eigen::Index>(j);
    correct(all);
  }
  SignedVolumesResult out;
  for (std::size_t j = 0; j < un; ++j) {
    v[j] = dead_[j] ? 0.0 : x[static_cast<Eigen::Index>(j)] / col_scale_[j];
    out.negative += v[j] < 0;
  }
  Real res = 0;
  for (std::size_t rr = 0; rr < um; ++rr) {
    Real s = -b[rr];
    for (std::size_t j = 0; j < un; ++j) s += A[rr * un + j] * v[j];
    res += s * s;
  }
  out.residual = std::sqrt(res);
  return out;
}

}  // namespace vrsph
