// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The pair weights of the generalized particle method ([IM](2)–(4), METHODS §3.8.1),
// shared by the particle stencils (methods/gpm/gpm.cpp) and the evaluation at arbitrary
// points (gpm_at): V_j the particle volume, w = w_h(r_j) the reference weight's value.
#include <vrsph/core/types.hpp>

namespace vrsph::gpm {

/// Interpolant (2): Pi_h v(x) = sum over |x_j - x| < h, x_j = x included, of value_weight * v_j.
inline Real value_weight(Real V, Real w) { return V * w; }
/// Gradient (3): nabla_h v(x) = sum_{x_j != x} gradient_weight * (v_j - v(x)), x_ji = x_j - x.
inline Vec3 gradient_weight(int d, Real V, Real w, Real r, const Vec3& x_ji) { return (d * V * w / (r * r)) * x_ji; }
/// Laplacian (4): Delta_h v(x) = sum_{x_j != x} laplacian_weight * (v_j - v(x)).
inline Real laplacian_weight(int d, Real V, Real w, Real r) { return 2 * d * V * w / (r * r); }

}  // namespace vrsph::gpm
