// SPDX-License-Identifier: BSD-3-Clause
// The periodic vortices of the flow studies (exact_flows.hpp).
#include <cmath>
#include <numbers>
#include <vrsph/flow/exact_flows.hpp>

namespace vrsph {

namespace {
constexpr Real kWave = 2 * std::numbers::pi;  // one wave per unit period
}

Real PeriodicVortex::decay_rate() const { return -(dim == 3 ? 1.0 : 2.0) * kWave * kWave * nu(); }

Vec3 PeriodicVortex::velocity(const Vec3& x, Real t) const {
  const Real a = U * std::exp(decay_rate() * t);
  if (dim == 3)
    return a * Vec3(std::sin(kWave * x[2]) + std::cos(kWave * x[1]), std::sin(kWave * x[0]) + std::cos(kWave * x[2]),
                    std::sin(kWave * x[1]) + std::cos(kWave * x[0]));
  return a * Vec3(-std::cos(kWave * x[0]) * std::sin(kWave * x[1]), std::sin(kWave * x[0]) * std::cos(kWave * x[1]), 0);
}

Real PeriodicVortex::pressure(const Vec3& x, Real t) const {
  if (dim == 3) {
    // -|u|²/2 less its mean over the cube (the mean of |u|² is 3 a²).
    const Real a = U * std::exp(decay_rate() * t);
    return -0.5 * velocity(x, t).squaredNorm() + 1.5 * a * a;
  }
  const Real a = U * std::exp(decay_rate() * t);
  return -0.25 * a * a * (std::cos(2 * kWave * x[0]) + std::cos(2 * kWave * x[1]));
}

Real PeriodicVortex::max_speed(Real t) const {
  // 3D: |u|² = a² (3 + 2 S), S = sin kz cos ky + sin kx cos kz + sin ky cos kx in [-3/2, 3/2].
  const Real a = U * std::exp(decay_rate() * t);
  return dim == 3 ? a * std::sqrt(6.0) : a;
}

Real PeriodicVortex::max_pressure(Real t) const {
  const Real a = U * std::exp(decay_rate() * t);
  // 2D: p ranges over ±a²/2. 3D: |u|² ranges over [0, 6 a²], so p - mean = 3a²/2 - |u|²/2 over [-3a²/2, 3a²/2].
  return dim == 3 ? 1.5 * a * a : 0.5 * a * a;
}

}  // namespace vrsph
