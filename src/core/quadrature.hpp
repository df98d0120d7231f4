// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: Gauss–Legendre quadrature, for kernel normalisations and the Neumann
// compatibility integrals.
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph::detail {

struct QuadratureRule {
  std::vector<Real> x, w;  ///< nodes and weights on [-1, 1]
};

/// n-point Gauss–Legendre rule (exact for polynomials of degree 2n - 1), by Newton
/// iteration on P_n.
QuadratureRule gauss_legendre(int n);

}  // namespace vrsph::detail
