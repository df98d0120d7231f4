// SPDX-License-Identifier: BSD-3-Clause
// [IM] reference weights (seed 004, METHODS §2.6–2.7): the tabulated 2D constants, the
// normalisation in every dimension, the vanishing moments Hypothesis 1 promises (checked by
// an independent quadrature of values), and the App. C construction reproducing the table.
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// |S^(d-1)| ∫_0^1 r^(d-1+m) w(r) dr by composite 3-point Gauss–Legendre on 400 cells (the cell
// edges include r = 1/2, where the spline pieces meet): exact for the polynomial pieces.
Real quadrature(const ReferenceWeight& w, int m) {
  const Real x[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)}, g[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  Real sum = 0;
  const int cells = 400;
  for (int c = 0; c < cells; ++c) {
    const Real a = Real(c) / cells, b = Real(c + 1) / cells;
    for (int k = 0; k < 3; ++k) {
      const Real r = 0.5 * (a + b) + 0.5 * (b - a) * x[k];
      sum += 0.5 * (b - a) * g[k] * std::pow(r, w.dim() - 1 + m) * w.value(r);
    }
  }
  return unit_sphere_area(w.dim()) * sum;
}
}  // namespace

TEST(ReferenceWeight, TabulatedTwoDimensionalConstants) {
  const Real kPi = std::numbers::pi, r = 0.3;
  EXPECT_NEAR(reference_weight("pi1", 2).value(r), 3 / kPi * (1 - r), 1e-13);
  EXPECT_NEAR(reference_weight("pi2", 2).value(r), 40 / (7 * kPi) * (1 - 6 * r * r + 6 * r * r * r), 1e-13);
  EXPECT_NEAR(reference_weight("pi3", 2).value(r), 6 / kPi * (1 - r) * (2 - 3 * r), 1e-13);  // S1: 6/π, not 5/π
  EXPECT_NEAR(reference_weight("grad1", 2).value(r), 6 / kPi * r * (1 - r), 1e-13);
  EXPECT_NEAR(reference_weight("grad2", 2).value(r), 40 / (7 * kPi) * (6 * r * r - 9 * r * r * r), 1e-13);
  EXPECT_NEAR(reference_weight("grad2", 2).value(0.7), 40 / (7 * kPi) * 3 * 0.7 * 0.09, 1e-13);
  EXPECT_NEAR(reference_weight("grad3", 2).value(r), 15 / (2 * kPi) * r * (1 - r) * (5 - 7 * r), 1e-13);
  EXPECT_NEAR(reference_weight("delta1", 2).value(r), 10 / kPi * r * r * (1 - r), 1e-13);
  EXPECT_NEAR(reference_weight("delta3", 2).value(r), 30 / kPi * r * r * (1 - r) * (3 - 4 * r), 1e-13);
  EXPECT_EQ(reference_weight("delta2", 2).value(r), reference_weight("grad2", 2).value(r));
  EXPECT_EQ(reference_weight("pi1", 2).value(1.0), 0);
  EXPECT_EQ(reference_weight("pi1", 2).value(1.5), 0);
  EXPECT_THROW_MSG(reference_weight("pi4", 2), ConfigError, "unknown reference weight 'pi4'");
  EXPECT_THROW_MSG(reference_weight("pi1", 4), ConfigError, "dimension must be 1, 2 or 3");
}

TEST(ReferenceWeight, NormalisedInEveryDimensionWithThePromisedMoments) {
  for (int d = 1; d <= 3; ++d)
    for (const auto& name : reference_weight_names()) {
      const ReferenceWeight w = reference_weight(name, d);
      EXPECT_NEAR(quadrature(w, 0), 1, 1e-13) << name << " " << d << "D";
      EXPECT_NEAR(unit_sphere_area(d) * w.radial_moment(0), 1, 1e-13) << name;
      const bool third = name.back() == '3';
      EXPECT_EQ(w.hypothesis1_order(), third ? 3 : 1) << name << " " << d << "D";
      if (third) {
        EXPECT_NEAR(quadrature(w, 2), 0, 1e-13) << name << " " << d << "D";  // second radial moment vanishes
      } else {
        EXPECT_GT(std::abs(quadrature(w, 2)), 1e-3) << name;
      }
      const int k = name.rfind("pi", 0) == 0 ? -1 : name.rfind("grad", 0) == 0 ? (name == "grad2" ? 1 : 0) : 1;
      EXPECT_EQ(w.hypothesis2_order(), k) << name;
    }
  // grad2 = -(1/d) r pi2'(r): SPH's kernel gradient as a weight.
  for (int d = 1; d <= 3; ++d)
    for (Real r : {0.1, 0.4, 0.6, 0.9})
      EXPECT_NEAR(reference_weight("grad2", d).value(r), -r / d * reference_weight("pi2", d).derivative(r), 1e-13);
}

TEST(ReferenceWeight, AppendixCConstructionReproducesTheTableAndMeetsHigherOrders) {
  const WeightOperator ops[3] = {WeightOperator::Interpolant, WeightOperator::Gradient, WeightOperator::Laplacian};
  const char* base[3] = {"pi", "grad", "delta"};
  for (int o = 0; o < 3; ++o)
    for (int n : {1, 3}) {
      const ReferenceWeight built = construct_reference_weight(2, ops[o], n);
      const ReferenceWeight table = reference_weight(std::string(base[o]) + (n == 1 ? "1" : "3"), 2);
      for (Real r = 0; r < 1; r += 0.05) EXPECT_NEAR(built.value(r), table.value(r), 1e-13) << table.name() << " r=" << r;
    }
  for (int d = 1; d <= 3; ++d)
    for (int o = 0; o < 3; ++o)
      for (int n : {1, 3, 5, 7})
        for (bool smooth : {false, true}) {
          const ReferenceWeight w = construct_reference_weight(d, ops[o], n, smooth);
          EXPECT_NEAR(quadrature(w, 0), 1, 1e-11) << w.name() << " " << d << "D";
          // The App. C system is Hilbert-like (condition ~1e8 at n = 7): 1e-9.
          for (int j = 1; j <= n / 2; ++j) EXPECT_NEAR(quadrature(w, 2 * j), 0, 1e-9) << w.name() << " j=" << j;
          EXPECT_GE(w.hypothesis1_order(), n) << w.name();
          EXPECT_EQ(w.hypothesis2_order(), o - 1) << w.name();
          EXPECT_NEAR(w.value(1 - 1e-12), 0, 1e-9) << w.name();                 // continuous at r = 1
          if (smooth) {
            EXPECT_NEAR(w.derivative(1 - 1e-12), 0, 1e-8) << w.name();  // and flat there
          }
        }
  EXPECT_THROW_MSG(construct_reference_weight(2, WeightOperator::Gradient, 2), ConfigError, "must be odd");
}
