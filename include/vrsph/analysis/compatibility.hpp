// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Solvability of a pure-Neumann problem div(a grad u) = f in Ω, a ∂u/∂n = q on ∂Ω:
// by the divergence theorem a solution exists only if ∮ q dS = ∫ f dV. Both sides are
// computed by Gauss–Legendre quadrature on the exact domain (box or ball, 1D–3D), at
// two orders so that the quadrature error itself is known and never mistaken for an
// incompatibility.
#include <functional>
#include <vrsph/cloud/domain.hpp>

namespace vrsph {

struct NeumannBalance {
  Real flux = 0;          ///< ∮ q dS
  Real source = 0;        ///< ∫ f dV
  Real scale = 0;         ///< ∮ |q| dS + ∫ |f| dV
  Real quadrature_error = 0;  ///< estimated error of flux - source
  /// |flux - source| within max(1e-8 scale, 10 x quadrature error).
  bool compatible() const;
};

/// q(x, n) gets the point and the outward unit normal. Throws ConfigError for a
/// domain without a known shape.
NeumannBalance neumann_balance(const Domain& domain, const std::function<Real(const Vec3&)>& f,
                               const std::function<Real(const Vec3&, const Vec3&)>& q);

}  // namespace vrsph
