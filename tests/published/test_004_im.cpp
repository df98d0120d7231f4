// SPDX-License-Identifier: BSD-3-Clause
// [IM] (seed 004_9e9d00b5a1203d0f.txt): Table 1 / Fig. 5 claims on the levels CI affords,
// the Table 1 particle sets, and the regularity indicators of those sets.
#include <cmath>
#include <vrsph/reproduce/im_table1.hpp>
#include <vrsph/analysis/regularity.hpp>
#include <vrsph/cloud/im_cloud.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(ImTable1, ParticleSetsAsInFig4) {
  const PointCloud c = im_cloud({.dim = 2, .dx = 1.0 / 32});
  EXPECT_EQ(c.size(), 39 * 39);  // METHODS §5.4: lattice points in Omega_H, then perturbed
  for (const auto& x : c.positions)
    for (int k = 0; k < 2; ++k) {
      const double offset = x[k] * 32 - std::round(x[k] * 32);
      EXPECT_LE(std::abs(offset), 0.25);
    }
}

// Fig. 5 claims: with h fixed in units of dx (m = 1) nothing converges and the Laplacian
// diverges at order ~ -1; with m = 3 and 5 every weight converges at least at Theorem 3's
// rate (least-squares order over dx = 2^-5 ... 2^-9, all particles of Omega up to 2^-7,
// 4000-point subsets beyond; band 0.3 below the theory).
TEST(ImTable1, Figure5Claims) {
  ImTable1Options o;
  o.levels = {5, 6, 7, 8, 9};
  o.max_points = 4000;
  const auto rows = im_table1(o);
  ASSERT_EQ(rows.size(), 5u * 3 * 9);
  for (const auto& r : rows) {
    if (r.level != 9) continue;
    SCOPED_TRACE(r.weight + " m=" + std::to_string(r.m));
    if (r.m == 1) {
      if (r.weight.rfind("delta", 0) == 0)
        EXPECT_NEAR(r.order_fit, -1.0, 0.3);
      else
        EXPECT_NEAR(r.order_fit, 0.0, 0.4);  // no convergence
    } else {
      EXPECT_GE(r.order_fit, im_theoretical_order(r.weight, r.m) - 0.3);
    }
  }
}

// [IM]'s own measure, the rate between two consecutive levels, on the finest pair CI affords
// (2^-8 -> 2^-9): with |Omega_H| / N it swings with the level's volume bias (pi1, m = 3: 1.22,
// as the bias goes from +1.3e-3 to -2.0e-3); with the cell volumes, the same particles reach
// Theorem 3's rate (2.2-8.6 at these levels with 10^4 points, 2.0-3.5 at 2^-11 -> 2^-12 over
// four seeds).
TEST(ImTable1, TwoLevelRatesReachTheoryWithoutVolumeBias) {
  ImTable1Options o;
  o.m = {3, 5};
  o.levels = {8, 9};
  o.max_points = 4000;
  o.volumes = ImVolumes::Cells;
  for (const auto& r : im_table1(o)) {
    if (r.level != 9) continue;
    SCOPED_TRACE(r.weight + " m=" + std::to_string(r.m));
    EXPECT_GE(r.order, im_theoretical_order(r.weight, r.m) - 0.3);
  }
}

// Why the two-level rates of Table 1 fall short of 2 at m = 3, 5 (1.5-1.8 at 2^-11 -> 2^-12,
// docs/im_regularity.md): the lattice does not tile Omega_H, so V_i = |Omega_H| / N is
// (1 + beta) dx^2 with a level-dependent beta = O(dx), and the sums carry that factor. At m = 5
// the quadrature error has faded by dx = 2^-10, and error_rel is the integral operator's
// |1 - (1 + beta) mu(|k| h)|. The same particles with cell volumes (dx^2 inside) differ by
// exactly -beta mu.
TEST(ImTable1, VolumeBiasAndSmoothingExplainTheErrors) {
  ImTable1Options o;
  o.weights = {"pi1", "grad1"};
  o.m = {5};
  o.levels = {9, 10};
  o.max_points = 2000;
  const auto uniform = im_table1(o);
  o.volumes = ImVolumes::Cells;
  const auto cells = im_table1(o);
  ASSERT_EQ(uniform.size(), 4u);
  ASSERT_EQ(cells.size(), 4u);
  for (std::size_t i = 0; i < uniform.size(); ++i) {
    const auto &u = uniform[i], &c = cells[i];
    SCOPED_TRACE(u.weight + " level " + std::to_string(u.level));
    const double beta = 1.44 / (static_cast<double>(u.particles) * u.dx * u.dx) - 1;
    EXPECT_NEAR(u.volume_bias, beta, 1e-12);
    EXPECT_GT(std::abs(beta), 3e-4);  // -1.95e-3 and -3.3e-4 at these levels
    EXPECT_EQ(c.volume_bias, 0);
    for (const auto* r : {&u, &c}) EXPECT_GT(r->error_rel, 0.97 * r->error_integral);
    const double mu = 1 - c.error_integral;  // mu < 1 here
    EXPECT_NEAR(u.error_rel - c.error_rel, -beta * mu, 0.1 * std::abs(beta));
    if (u.level == 10 && u.weight == "pi1") {
      EXPECT_LT(u.error_rel, 1.06 * u.error_integral);
      EXPECT_LT(c.error_rel, 1.06 * c.error_integral);
    }
  }
}

// The sets are regular: r_N + d_N stays a bounded multiple of dx under refinement (so any
// order m is reached by h ~ dx^(1/m)), with d_N = 0 for Voronoi volumes. The multiple is
// not constant: |Omega_H| / N differs from dx^2 by a level-dependent O(dx) (METHODS S8),
// and that surplus has to be carried across the set.
TEST(ImRegularity, IndicatorsScaleWithDx) {
  VRSPH_REQUIRE_PART("CGAL");  // covering radius and Voronoi cells
  VRSPH_REQUIRE_PART("CLP");   // the Voronoi deviation LP
  for (int n : {16, 32}) {
    const PointCloud c = im_cloud({.dim = 2, .dx = 1.0 / n});
    const RegularityReport r = regularity(c);
    const double kappa = (r.covering.radius + r.deviation.value) * n;
    EXPECT_GT(kappa, 0.5);
    EXPECT_LT(kappa, 4.0);
    RegularityOptions vo;
    vo.volumes = ParticleVolumes::Voronoi;
    EXPECT_NEAR(regularity(c, vo).deviation.value, 0, 1e-8 / n);  // Clp tolerance 1e-9 in cell units
  }
}
