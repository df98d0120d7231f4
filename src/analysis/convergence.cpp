// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <limits>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

std::vector<Real> pairwise_orders(std::span<const Real> s, std::span<const Real> e) {
  check<InputError>(s.size() == e.size(), "pairwise_orders: ", s.size(), " sizes but ", e.size(), " errors");
  std::vector<Real> out(s.size(), std::numeric_limits<Real>::quiet_NaN());
  for (std::size_t k = 1; k < s.size(); ++k) {
    if (e[k] > 0 && e[k - 1] > 0 && std::isfinite(e[k]) && std::isfinite(e[k - 1]) && s[k] != s[k - 1])
      out[k] = std::log(e[k - 1] / e[k]) / std::log(s[k - 1] / s[k]);
  }
  return out;
}

Real least_squares_order(std::span<const Real> s, std::span<const Real> e) {
  check<InputError>(s.size() == e.size(), "least_squares_order: ", s.size(), " sizes but ", e.size(), " errors");
  Real n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (!(e[k] > 0) || !std::isfinite(e[k]) || !(s[k] > 0)) continue;
    const Real x = std::log(s[k]), y = std::log(e[k]);
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const Real den = n * sxx - sx * sx;
  if (n < 2 || den == 0) return std::numeric_limits<Real>::quiet_NaN();
  return (n * sxy - sx * sy) / den;
}

}  // namespace vrsph
