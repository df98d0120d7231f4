// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the compact rows' tests check a row against: p = x^3 y - 2 x y^2 + y^4 and
// L p = a Δp + ∇a·∇p for a = 1 + x^2 + y. A row exact on quartics has
// Σ_j w_ij p_j = Σ_k μ_ik (L p)(x_k) (its diagonal in difference form).
#include <algorithm>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph::test {

inline Real quartic(const Vec3& x) { return x[0] * x[0] * x[0] * x[1] - 2 * x[0] * x[1] * x[1] + x[1] * x[1] * x[1] * x[1]; }
inline Real quartic_coefficient(const Vec3& x) { return 1 + x[0] * x[0] + x[1]; }
inline Real quartic_laplacian(const Vec3& x) { return 6 * x[0] * x[1] - 4 * x[0] + 12 * x[1] * x[1]; }
inline Real quartic_operator(const Vec3& x) {
  const Real px = 3 * x[0] * x[0] * x[1] - 2 * x[1] * x[1], py = x[0] * x[0] * x[0] - 4 * x[0] * x[1] + 4 * x[1] * x[1] * x[1];
  return quartic_coefficient(x) * quartic_laplacian(x) + 2 * x[0] * px + py;
}

// Row i of a compact stencil applied to the quartic: both sides, Σ μ, the signs of its weights
// and the distance (in units of h) of the farthest particle it weighs.
struct CompactRowSums {
  Real lhs = 0, rhs = 0, mu_sum = 0, farthest = 0;
  bool negative_w = false, negative_mu = false;
  bool exact(Real tolerance) const { return std::abs(lhs - rhs) < tolerance * (1 + std::abs(rhs)); }
};
inline CompactRowSums compact_row_sums(const Stencil& L, const PointCloud& c, Index i, Real h = 1) {
  CompactRowSums r;
  for (Index k = L.row_begin(i); k < L.row_end(i); ++k) {
    const auto sk = static_cast<std::size_t>(k);
    const Index j = L.col[sk];
    const Vec3& xj = c.positions[static_cast<std::size_t>(j)];
    r.lhs += L.values[0][sk] * quartic(xj);
    r.rhs += L.rhs[sk] * quartic_operator(xj);
    r.mu_sum += L.rhs[sk];
    r.negative_mu = r.negative_mu || L.rhs[sk] < 0;
    r.negative_w = r.negative_w || (j != i && L.values[0][sk] < 0);
    if (L.values[0][sk] != 0 || L.rhs[sk] != 0)
      r.farthest = std::max(r.farthest, (xj - c.positions[static_cast<std::size_t>(i)]).norm() / h);
  }
  return r;
}

}  // namespace vrsph::test
