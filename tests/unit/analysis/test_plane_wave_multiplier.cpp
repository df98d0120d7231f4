// SPDX-License-Identifier: BSD-3-Clause
// The plane-wave multipliers of [IM]'s integral operators (analysis/plane_wave_multiplier.hpp):
// against a brute-force Cartesian quadrature of the integrals themselves, and against the
// moment expansion mu = 1 - s^2 M2 / (2d) + O(s^4) that Hypothesis 1 controls.
#include <cmath>
#include <vrsph/analysis/plane_wave_multiplier.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
const char* const weights[] = {"pi1", "pi2", "pi3", "grad1", "grad2", "grad3", "delta1", "delta2", "delta3"};

// The operator (2), (3) or (4) with its sum replaced by a midpoint rule on cells of side
// `step` over [-1, 1]^d (h = 1), applied at x = 0 to v = sin(k.y + phi), divided by what the
// exact operator gives there: mu.
Real brute_force_multiplier(const ReferenceWeight& w, WeightOperator op, const Vec3& k, Real step) {
  const int d = w.dim();
  const Real phi = 0.3;
  const int n = static_cast<int>(std::lround(2 / step));
  const Real cell = std::pow(step, d);
  Real sum = 0;
  const int ny = d > 1 ? n : 1, nz = d > 2 ? n : 1;
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < n; ++a) {
        Vec3 y = Vec3::Zero();
        y[0] = -1 + (a + 0.5) * step;
        if (d > 1) y[1] = -1 + (b + 0.5) * step;
        if (d > 2) y[2] = -1 + (c + 0.5) * step;
        const Real r = y.norm();
        if (r >= 1) continue;
        const Real v = std::sin(k.dot(y) + phi), dv = v - std::sin(phi);
        const Real wr = w.value(r) * cell;
        if (op == WeightOperator::Interpolant) sum += wr * v;
        else if (op == WeightOperator::Gradient) sum += d * wr * dv * y.dot(k) / (r * r);  // along k
        else sum += 2 * d * wr * dv / (r * r);
      }
  const Real k2 = k.squaredNorm();
  return op == WeightOperator::Interpolant ? sum / std::sin(phi)
         : op == WeightOperator::Gradient  ? sum / (k2 * std::cos(phi))
                                           : sum / (-k2 * std::sin(phi));
}
}  // namespace

TEST(PlaneWaveMultiplier, MatchesBruteForceQuadratureInEveryDimension) {
  // The midpoint rule's error on the kinks of w (at r = 1 and r = 1/2) sets the tolerance.
  const Real step[] = {0, 2e-4, 2e-3, 2.5e-2}, tol[] = {0, 1e-7, 2e-7, 1e-4};
  for (int d = 1; d <= 3; ++d) {
    Vec3 k = Vec3::Zero();
    k[0] = 2.1;
    if (d > 1) k[1] = -1.3;
    if (d > 2) k[2] = 0.8;
    for (const char* name : weights) {
      SCOPED_TRACE(std::string(name) + " d=" + std::to_string(d));
      const ReferenceWeight w = reference_weight(name, d);
      const WeightOperator op = reference_weight_operator(name);
      const Real mu = plane_wave_multiplier(w, op, k.norm());
      EXPECT_NEAR(mu, brute_force_multiplier(w, op, k, step[d]), tol[d]);
      EXPECT_LT(mu, 1);  // these weights smooth: every one damps the wave at |k| h = O(1)
    }
  }
}

TEST(PlaneWaveMultiplier, SmallWavenumberExpansion) {
  for (int d = 1; d <= 3; ++d)
    for (const char* name : weights) {
      SCOPED_TRACE(std::string(name) + " d=" + std::to_string(d));
      const ReferenceWeight w = reference_weight(name, d);
      const WeightOperator op = reference_weight_operator(name);
      EXPECT_NEAR(plane_wave_multiplier(w, op, 0), 1, 1e-13);
      // The interpolant's second moment, exactly: zero for the n = 3 weights (Hypothesis 1).
      if (op == WeightOperator::Interpolant) {
        const Real s = 1e-2, M2 = unit_sphere_area(d) * w.radial_moment(2);
        EXPECT_NEAR(plane_wave_multiplier(w, op, s), 1 - s * s * M2 / (2 * d), 1e-8);
        if (w.hypothesis1_order() >= 3) {
          EXPECT_NEAR(1 - plane_wave_multiplier(w, op, s), 0, 1e-8);
        }
      }
    }
}

TEST(PlaneWaveMultiplier, RejectsBadWavenumber) {
  const ReferenceWeight w = reference_weight("pi1", 2);
  EXPECT_THROW(plane_wave_multiplier(w, WeightOperator::Interpolant, -1), ConfigError);
  EXPECT_THROW(plane_wave_multiplier(w, WeightOperator::Interpolant, std::nan("")), ConfigError);
}
