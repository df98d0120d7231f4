// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/analysis/plane_wave_multiplier.hpp>
#include <vrsph/core/error.hpp>
#include "../core/quadrature.hpp"

namespace vrsph {

namespace {
// j_d(z), and the two bounded quotients the gradient and Laplacian need, with series where
// the closed forms cancel (z < 1e-3: the next series term is below 1e-18).
Real sphere_mean_cos(int d, Real z) {
  if (d == 1) return std::cos(z);
  if (d == 2) return std::cyl_bessel_j(0.0, z);
  return z < 1e-3 ? 1 - z * z / 6 : std::sin(z) / z;
}
Real gradient_quotient(int d, Real z) {  // -j_d'(z) / z -> 1/d
  if (d == 1) return z < 1e-3 ? 1 - z * z / 6 : std::sin(z) / z;
  if (d == 2) return z < 1e-3 ? 0.5 - z * z / 16 : std::cyl_bessel_j(1.0, z) / z;
  return z < 1e-3 ? 1.0 / 3 - z * z / 30 : (std::sin(z) - z * std::cos(z)) / (z * z * z);
}
Real laplacian_quotient(int d, Real z) {  // (1 - j_d(z)) / z^2 -> 1/(2d)
  if (d == 1) {
    const Real s = z < 1e-3 ? 0.5 : std::sin(z / 2) / z;
    return 2 * s * s;
  }
  if (d == 2) return z < 1e-3 ? 0.25 - z * z / 64 : (1 - std::cyl_bessel_j(0.0, z)) / (z * z);
  return z < 1e-3 ? 1.0 / 6 - z * z / 120 : (z - std::sin(z)) / (z * z * z);
}
}  // namespace

Real plane_wave_multiplier(const ReferenceWeight& w, WeightOperator op, Real s) {
  check<ConfigError>(std::isfinite(s) && s >= 0, "plane_wave_multiplier: s must be finite and >= 0, got ", s);
  const int d = w.dim();
  static const detail::QuadratureRule gl = detail::gauss_legendre(12);
  constexpr int panels = 16;
  Real integral = 0;
  for (const auto& piece : w.pieces())
    for (int p = 0; p < panels; ++p) {
      const Real a = piece.from + (piece.to - piece.from) * p / panels, b = piece.from + (piece.to - piece.from) * (p + 1) / panels;
      for (std::size_t k = 0; k < gl.x.size(); ++k) {
        const Real r = 0.5 * (a + b) + 0.5 * (b - a) * gl.x[k];
        const Real z = s * r;
        const Real f = op == WeightOperator::Interpolant ? sphere_mean_cos(d, z)
                       : op == WeightOperator::Gradient  ? d * gradient_quotient(d, z)
                                                         : 2 * d * laplacian_quotient(d, z);
        integral += 0.5 * (b - a) * gl.w[k] * std::pow(r, d - 1) * w.value(r) * f;
      }
    }
  return unit_sphere_area(d) * integral;
}

}  // namespace vrsph
