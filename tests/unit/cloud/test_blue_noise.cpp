// SPDX-License-Identifier: BSD-3-Clause
// Blue-noise point sets: the exclusion radius holds, the sets are maximal (no hole wider than
// the growth shell allows), the density matches the lattice's, and a seed fixes the result.
#include <cmath>
#include <vrsph/cloud/blue_noise.hpp>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
Real min_pair_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  Real d = 1e300;
  for (const auto& x : a)
    for (const auto& y : b)
      if (&x != &y) d = std::min(d, (x - y).norm());
  return d;
}
}  // namespace

TEST(BlueNoise, GrownSetKeepsTheRadiusFillsTheDomainAndMatchesTheLatticeDensity) {
  for (int dim : {2, 3}) {
    const Real s = dim == 2 ? 0.02 : 0.05, r = blue_noise_radius_factor(dim) * s;
    const auto in_box = [dim](const Vec3& x) {
      for (int k = 0; k < dim; ++k)
        if (x[k] < 0 || x[k] > 1) return false;
      return true;
    };
    const std::vector<Vec3> seeds = {Vec3(0.5, dim > 1 ? 0.5 : 0, dim > 2 ? 0.5 : 0)};
    const auto pts = grow_blue_noise(dim, r, seeds, in_box, 7);
    for (const auto& x : pts) ASSERT_TRUE(in_box(x));
    EXPECT_GE(min_pair_distance(pts, pts), r * (1 - 1e-12)) << "dim " << dim;
    // About one point per s^d (the factor's promise; boundary losses in a unit box at this
    // resolution are a few per cent).
    const Real expected = std::pow(1 / s, dim);
    EXPECT_NEAR(static_cast<Real>(pts.size() + 1) / expected, 1.0, 0.06) << "dim " << dim << ": " << pts.size();
    // No big holes: every point of a probe lattice has a point within 2r (Bridson's shell).
    std::vector<Vec3> all = pts;
    all.push_back(seeds[0]);
    for (Real px = 0.1; px < 0.95; px += 0.2)
      for (Real py = 0.1; py < 0.95; py += 0.2) {
        const Vec3 probe(px, py, dim > 2 ? 0.3 : 0);
        Real d = 1e300;
        for (const auto& x : all) d = std::min(d, (x - probe).norm());
        EXPECT_LE(d, 2 * r) << probe.transpose();
      }
    EXPECT_EQ(grow_blue_noise(dim, r, seeds, in_box, 7), pts);  // the seed fixes the set
    EXPECT_NE(grow_blue_noise(dim, r, seeds, in_box, 8), pts);
  }
}

TEST(BlueNoise, ThinningKeepsTheRadiusAgainstItselfAndTheFixedPointsAndIsMaximal) {
  std::vector<Vec3> cand;
  for (int k = 0; k < 4000; ++k) cand.emplace_back(std::fmod(k * 0.6180339887, 1.0), std::fmod(k * 0.7548776662, 1.0), 0);
  const std::vector<Vec3> fixed = {Vec3(0.5, 0.5, 0), Vec3(0.1, 0.9, 0)};
  const Real r = 0.05;
  const auto kept = thin_to_blue_noise(cand, r, fixed, 3);
  std::vector<Vec3> pts;
  for (auto k : kept) pts.push_back(cand[k]);
  EXPECT_GE(min_pair_distance(pts, pts), r);
  EXPECT_GE(min_pair_distance(pts, fixed), r);
  // Maximal: every candidate left out has a kept or fixed point closer than r.
  for (const auto& c : cand) {
    Real d = min_pair_distance({c}, fixed);
    for (const auto& x : pts) d = std::min(d, (x - c).norm());
    EXPECT_LT(d, r + 1e-15);
  }
  EXPECT_EQ(thin_to_blue_noise(cand, r, fixed, 3), kept);
}

TEST(BlueNoise, BadArgumentsAreConfigErrors) {
  const auto any = [](const Vec3&) { return true; };
  EXPECT_THROW_MSG(grow_blue_noise(2, 0, {Vec3::Zero()}, any, 1), ConfigError, "exclusion radius must be positive");
  EXPECT_THROW_MSG(grow_blue_noise(4, 0.1, {Vec3::Zero()}, any, 1), ConfigError, "dimension must be 1, 2 or 3");
  EXPECT_THROW_MSG(thin_to_blue_noise({}, std::nan(""), {}, 1), ConfigError, "exclusion radius must be positive");
  EXPECT_TRUE(grow_blue_noise(2, 0.1, {}, any, 1).empty());  // nothing to grow from
}
