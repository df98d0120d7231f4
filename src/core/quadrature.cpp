// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include "quadrature.hpp"

namespace vrsph::detail {

QuadratureRule gauss_legendre(int n) {
  QuadratureRule r;
  const auto nr = static_cast<Real>(n);
  for (int i = 0; i < n; ++i) {
    Real z = std::cos(std::numbers::pi * (static_cast<Real>(i) + 0.75) / (nr + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      Real p0 = 1, p1 = z;
      for (int kk = 2; kk <= n; ++kk) {
        const auto k = static_cast<Real>(kk);
        const Real p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = nr * (z * p1 - p0) / (z * z - 1);
      const Real dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    r.x.push_back(z);
    r.w.push_back(2 / ((1 - z * z) * dp * dp));
  }
  return r;
}

}  // namespace vrsph::detail
