// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Observed orders of convergence: pairwise log(e_k/e_{k+1}) / log(s_k/s_{k+1}) with s a
// mesh size (dx or h), and the least-squares slope of log e against log s.
#include <span>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

/// First entry NaN; NaN where an error is zero or not finite.
std::vector<Real> pairwise_orders(std::span<const Real> sizes, std::span<const Real> errors);
/// NaN with fewer than two usable points.
Real least_squares_order(std::span<const Real> sizes, std::span<const Real> errors);

}  // namespace vrsph
