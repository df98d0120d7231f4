// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The continuous operators the generalized particle method's sums approximate ([IM] (2)–(4)
// with the sums replaced by integrals over R^d) act on a plane wave v = sin(k·x) as
// multiplication: Pi v = mu v, nabla v = mu grad v, Delta v = mu Delta v, with mu a radial
// transform of the weight at s = |k| h:
//   interpolant  mu = |S| ∫ w(r) r^(d-1) j_d(s r) dr,
//   gradient     mu = d |S| ∫ w(r) r^(d-1) (-j_d'(z) / z)|_(z = s r) dr,
//   Laplacian    mu = 2d |S| ∫ w(r) r^(d-1) ((1 - j_d(z)) / z^2)|_(z = s r) dr,
// j_d the sphere average of cos(z cos θ): cos z, J0(z), sin z / z for d = 1, 2, 3. So
// |1 - mu| is the part of a truncation error that no particle arrangement can remove (the
// smoothing error, O(h^(n+1)) under Hypothesis 1 of order n), and mu -> 1 as s -> 0 for every
// normalised weight. Used to split [IM] Table 1's errors into smoothing and quadrature.
#include <vrsph/core/types.hpp>
#include <vrsph/kernels/reference_weight.hpp>

namespace vrsph {

/// mu(s) for the weight in its own dimension; s >= 0. Composite Gauss–Legendre over each
/// polynomial piece of w (16 panels of 12 points), accurate to round-off for s <= 50.
Real plane_wave_multiplier(const ReferenceWeight& w, WeightOperator op, Real s);

}  // namespace vrsph
