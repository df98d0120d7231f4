// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/kernel.hpp>
#include "test_util.hpp"

using namespace vrsph;
constexpr double pi = std::numbers::pi;

struct KernelCase {
  KernelType type;
  int dim;
};
class KernelAll : public ::testing::TestWithParam<KernelCase> {};

// Integral over R^d by a midpoint lattice sum; for compactly supported smooth
// profiles this converges fast, so 1e-4 is a safe band.
TEST_P(KernelAll, IntegratesToOne) {
  const auto [type, dim] = GetParam();
  const Kernel k(type, dim, 1.3);
  const int m = dim == 3 ? 40 : 200;
  const double step = 1.3 / m;
  double sum = 0;
  for (int a = -m; a < m; ++a)
    for (int b = (dim > 1 ? -m : 0); b < (dim > 1 ? m : 1); ++b)
      for (int c = (dim > 2 ? -m : 0); c < (dim > 2 ? m : 1); ++c) {
        const double x = (a + 0.5) * step, y = dim > 1 ? (b + 0.5) * step : 0, z = dim > 2 ? (c + 0.5) * step : 0;
        sum += k.W(std::sqrt(x * x + y * y + z * z));
      }
  EXPECT_NEAR(sum * std::pow(step, dim), 1.0, 1e-4) << kernel_info(type).name << " d=" << dim;
}

TEST_P(KernelAll, DecaysMonotonicallyAndDerivativesMatchFiniteDifferences) {
  const auto [type, dim] = GetParam();
  const Kernel k(type, dim, 0.7);
  const double eps = 1e-6;
  double prev = k.W(0);
  for (int s = 1; s < 700; ++s) {
    const double r = 0.001 * s;
    SCOPED_TRACE(testing::Message() << kernel_info(type).name << " d=" << dim << " r=" << r);
    EXPECT_LE(k.W(r), prev + 1e-14);
    prev = k.W(r);
    EXPECT_LE(k.dW(r), 1e-14);
    const double fd = (k.W(r + eps) - k.W(r - eps)) / (2 * eps);
    EXPECT_NEAR(k.dW(r), fd, 1e-6 * (1 + std::abs(fd)));
    const double fd2 = (k.dW(r + eps) - k.dW(r - eps)) / (2 * eps);
    // Cubic and quintic splines have kinks in W'' at their knots; skip the knots.
    bool near_knot = false;
    for (double knot : {0.7 / 3, 0.35, 0.7 * 2 / 3})
      near_knot = near_knot || std::abs(r - knot) < 2 * eps;
    if (!near_knot) {
      EXPECT_NEAR(k.d2W(r), fd2, 1e-5 * (1 + std::abs(fd2)));
    }
    EXPECT_NEAR(k.dW_over_r(r), k.dW(r) / r, 1e-12 * (1 + std::abs(k.dW(r) / r)));
  }
  EXPECT_EQ(k.W(0.7), 0.0);
  EXPECT_EQ(k.W(1.0), 0.0);
  EXPECT_NEAR(k.dW_over_r(0), k.d2W(0), 1e-12 * std::abs(k.d2W(0)));
}

INSTANTIATE_TEST_SUITE_P(AllKernels, KernelAll,
                         ::testing::Values(KernelCase{KernelType::CubicSpline, 1}, KernelCase{KernelType::CubicSpline, 2},
                                           KernelCase{KernelType::CubicSpline, 3}, KernelCase{KernelType::CubicSplineSPE, 1},
                                           KernelCase{KernelType::CubicSplineSPE, 2}, KernelCase{KernelType::CubicSplineSPE, 3},
                                           KernelCase{KernelType::Gaussian, 1}, KernelCase{KernelType::Gaussian, 2},
                                           KernelCase{KernelType::Gaussian, 3}, KernelCase{KernelType::Quintic, 1},
                                           KernelCase{KernelType::Quintic, 2}, KernelCase{KernelType::Quintic, 3},
                                           KernelCase{KernelType::WendlandC2, 1}, KernelCase{KernelType::WendlandC2, 2},
                                           KernelCase{KernelType::WendlandC2, 3}, KernelCase{KernelType::WendlandC4, 1},
                                           KernelCase{KernelType::WendlandC4, 2}, KernelCase{KernelType::WendlandC4, 3}));

// Published normalisation constants (METHODS §1.3, §2.4), converted to the
// support-radius form sigma_d in W = sigma_d h^-d w(r/h).
TEST(Kernel, NormalisationMatchesPublishedConstants) {
  auto sigma = [](KernelType t, int d) { return Kernel(t, d, 1.0).normalisation(); };
  EXPECT_NEAR(sigma(KernelType::CubicSpline, 1), 4.0 / 3, 1e-13);  // [QW](2.4)
  EXPECT_NEAR(sigma(KernelType::CubicSpline, 2), 40 / (7 * pi), 1e-13);
  EXPECT_NEAR(sigma(KernelType::CubicSpline, 3), 8 / pi, 1e-13);
  // [SPE](12): Xi_d l^-d with support 2l, so sigma_d = 2^d Xi_d; Xi_1 = 2/3 (erratum R1, printed 3/2).
  EXPECT_NEAR(sigma(KernelType::CubicSplineSPE, 1) / 2, 2.0 / 3, 1e-13);
  EXPECT_NEAR(sigma(KernelType::CubicSplineSPE, 2) / 4, 10 / (7 * pi), 1e-13);
  EXPECT_NEAR(sigma(KernelType::CubicSplineSPE, 3) / 8, 1 / pi, 1e-13);
  // Quintic, support 3l: c_1 = 1/120, c_2 = 7/(478 pi), c_3 = 1/(120 pi).
  EXPECT_NEAR(sigma(KernelType::Quintic, 1) / 3, 1.0 / 120, 1e-14);
  EXPECT_NEAR(sigma(KernelType::Quintic, 2) / 9, 7 / (478 * pi), 1e-14);
  EXPECT_NEAR(sigma(KernelType::Quintic, 3) / 27, 1 / (120 * pi), 1e-14);
  // Wendland C2, support 2l: 5/8 (1D), 7/(4 pi), 21/(16 pi).
  EXPECT_NEAR(sigma(KernelType::WendlandC2, 1) / 2, 5.0 / 8, 1e-13);
  EXPECT_NEAR(sigma(KernelType::WendlandC2, 2) / 4, 7 / (4 * pi), 1e-13);
  EXPECT_NEAR(sigma(KernelType::WendlandC2, 3) / 8, 21 / (16 * pi), 1e-13);
  // Wendland C4 (Dehnen & Aly 2012): 9/pi (2D), 495/(32 pi) (3D) in support-radius form for
  // the profile (1-R)^6 (1 + 6R + 35R^2/3); ours is 3x that polynomial, hence the /3.
  EXPECT_NEAR(sigma(KernelType::WendlandC4, 2), 9 / pi / 3, 1e-12);
  EXPECT_NEAR(sigma(KernelType::WendlandC4, 3), 495 / (32 * pi) / 3, 1e-12);
  // Gaussian of [AAR]: 1/(pi^{d/2} l^d) with support 6l.
  EXPECT_NEAR(sigma(KernelType::Gaussian, 2) / 36, 1 / pi, 1e-12);
}

TEST(Kernel, SmoothingLengthFormEqualsSupportRadiusForm) {
  for (int d = 1; d <= 3; ++d) {
    const Kernel qw(KernelType::CubicSpline, d, 0.6);
    const Kernel spe = Kernel::from_smoothing_length(KernelType::CubicSplineSPE, d, 0.3);
    ASSERT_DOUBLE_EQ(spe.support(), 0.6);
    for (double r = 0; r < 0.61; r += 0.01) {
      EXPECT_NEAR(qw.W(r), spe.W(r), 1e-12 * qw.W(0));
      EXPECT_NEAR(qw.dW(r), spe.dW(r), 1e-11 * std::abs(qw.d2W(0)));
    }
  }
}

TEST(Kernel, RejectsBadParameters) {
  EXPECT_THROW_MSG(Kernel(KernelType::CubicSpline, 2, 0.0), InputError, "support radius h must be positive");
  EXPECT_THROW_MSG(Kernel(KernelType::CubicSpline, 2, -1.0), InputError, "h = -1");
  EXPECT_THROW_MSG(Kernel(KernelType::CubicSpline, 4, 1.0), InputError, "dimension must be 1, 2 or 3");
  EXPECT_THROW_MSG(Kernel::from_smoothing_length(KernelType::Quintic, 2, std::nan("")), InputError, "smoothing length");
  EXPECT_THROW_MSG(parse_kernel("cubix"), ConfigError, "unknown kernel 'cubix'");
}

TEST(Kernel, BatchedDerivativeEqualsScalarForEveryKernel) {
  for (const auto& info : kernel_catalogue())
    for (int dim = 1; dim <= 3; ++dim) {
      const Kernel k(info.type, dim, 0.37);
      std::vector<double> r, out(41);
      for (int i = 0; i <= 40; ++i) r.push_back(0.37 * 1.05 * i / 40.0);  // includes r = 0, r = h and beyond
      k.dW_over_r(r.data(), out.data(), static_cast<int>(r.size()));
      for (std::size_t i = 0; i < r.size(); ++i)
        EXPECT_NEAR(out[i], k.dW_over_r(r[i]), 1e-12 * std::abs(k.dW_over_r(0)) + 1e-300) << info.name << " r=" << r[i];
    }
}
