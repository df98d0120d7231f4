// SPDX-License-Identifier: BSD-3-Clause
// [QW] (seed 000_906375e5ed7c9bb7.txt) Examples 1–4 with the Taylor-corrected comparators
// FPM, CSPM ("CSPH") and KGF beside SPH and VRSPH: the orders METHODS §5.1 states.
// Bands (least-squares order over n = 16..128, one seed): gradient of FPM/CSPM/KGF on
// perturbed particles in [0.7, 1.4] (order 1); FPM Laplacian "about 1 or worse"
// (<= 1.4) but convergent (>= 0.5); CSPM Laplacian below first order (<= 0.5);
// SPH non-convergent; VRSPH >= 1.8; on uniform lattices with ghosts FPM/KGF are exact for
// quadratics, so order 2 (>= 1.8).
#include <iostream>
#include <vrsph/analysis/operator_study.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
OperatorStudyResult compare(int dim, OperatorKind op, CloudFamily cloud, bool ghosts, double kappa, std::vector<int> n) {
  OperatorStudyParams p;
  p.dim = dim;
  p.methods = {"sph", "fpm", "cspm", "kgf", "vrsph"};
  p.method_options["vrsph"].set("profile", "qw");
  // The comparators as [QW] define them: FPM's and KGF's gradient from the linear fit ([QW]
  // (2.15)); their default rows are exact on cubics (docs/methods.md).
  p.method_options["fpm"].set("gradient_order", "1");
  p.method_options["kgf"].set("gradient_order", "1");
  p.op = op;
  p.cloud = cloud;
  p.ghosts = ghosts;
  p.h_factor = kappa;
  p.n = std::move(n);
  p.seed = 1;
  const auto r = run_operator_study(p);
  std::cout << to_markdown(to_table(r));
  return r;
}
}  // namespace

TEST(QwComparators, Example1UniformWithGhostsFpmKgfSecondOrder) {
  for (OperatorKind op : {OperatorKind::Gradient, OperatorKind::Laplacian}) {
    const auto r = compare(2, op, CloudFamily::Uniform, true, 3, {16, 32, 64, 128});
    EXPECT_GE(r.fitted_order_inf.at("fpm"), 1.8) << to_string(op);
    EXPECT_GE(r.fitted_order_inf.at("kgf"), 1.8) << to_string(op);
    EXPECT_GE(r.fitted_order_inf.at("vrsph"), 1.8) << to_string(op);
  }
}

TEST(QwComparators, Example2PerturbedGradientFirstOrder2D) {
  const auto r = compare(2, OperatorKind::Gradient, CloudFamily::Perturbed, true, 3, {16, 32, 64, 128});
  for (const auto* m : {"fpm", "cspm", "kgf"}) {
    EXPECT_GE(r.fitted_order_inf.at(m), 0.7) << m;
    EXPECT_LE(r.fitted_order_inf.at(m), 1.4) << m;
  }
  EXPECT_LE(std::abs(r.fitted_order_inf.at("sph")), 0.5);
  EXPECT_GE(r.fitted_order_inf.at("vrsph"), 1.8);
}

TEST(QwComparators, Example2PerturbedGradientFirstOrder1D) {
  const auto r = compare(1, OperatorKind::Gradient, CloudFamily::Perturbed, true, 3, {32, 64, 128, 256, 512});
  for (const auto* m : {"fpm", "cspm", "kgf"}) {
    EXPECT_GE(r.fitted_order_inf.at(m), 0.7) << m;
    EXPECT_LE(r.fitted_order_inf.at(m), 1.4) << m;
  }
}

TEST(QwComparators, Example2PerturbedLaplacian2D) {
  const auto r = compare(2, OperatorKind::Laplacian, CloudFamily::Perturbed, true, 3, {16, 32, 64, 128});
  EXPECT_GE(r.fitted_order_inf.at("fpm"), 0.5);
  EXPECT_LE(r.fitted_order_inf.at("fpm"), 1.4);
  // Two-sided: KGF must converge at first order and not more; CSPM's error stays O(1)
  // (the neglected off-diagonal Hessian terms) without diverging. Measured: 1.0 and -0.1.
  EXPECT_GE(r.fitted_order_inf.at("kgf"), 0.6);
  EXPECT_LE(r.fitted_order_inf.at("kgf"), 1.5);
  EXPECT_GE(r.fitted_order_inf.at("cspm"), -0.5);
  EXPECT_LE(r.fitted_order_inf.at("cspm"), 0.5);
  EXPECT_LE(r.fitted_order_inf.at("sph"), -0.7);  // diverges
  EXPECT_GE(r.fitted_order_inf.at("vrsph"), 1.8);
}

TEST(QwComparators, Example4NoGhostsGradientNearBoundary) {
  // Without ghosts the one-sided supports next to the boundary cost FPM/CSPM/KGF an order.
  const auto r = compare(2, OperatorKind::Gradient, CloudFamily::Uniform, false, 3, {16, 32, 64, 128});
  for (const auto* m : {"fpm", "cspm", "kgf"}) {  // measured 0.97, 0.84, 1.02
    EXPECT_GE(r.fitted_order_inf.at(m), 0.7) << m;
    EXPECT_LE(r.fitted_order_inf.at(m), 1.4) << m;
  }
  EXPECT_GE(r.fitted_order_inf.at("vrsph"), 1.8);
}

TEST(QwComparators, Example3TriangleCentroids) {
  VRSPH_REQUIRE_PART("CGAL");  // the centroid cloud is a CGAL Delaunay mesh
  // Our centroid clouds substitute [QW]'s MATLAB mesh (METHODS P12). On them FPM/KGF reach
  // order ~2 rather than [QW]'s "barely 1" (the substitute mesh is more regular; see the
  // report), so the assertions are the ones that hold for any such cloud: every corrected
  // gradient converges at least at first order, SPH's Laplacian does not converge, VRSPH 2.
  const auto g = compare(2, OperatorKind::Gradient, CloudFamily::Centroids, true, 4, {16, 32, 64});
  for (const auto* m : {"fpm", "cspm", "kgf"}) EXPECT_GE(g.fitted_order_inf.at(m), 0.7) << m;
  EXPECT_GE(g.fitted_order_inf.at("vrsph"), 1.8);
  const auto l = compare(2, OperatorKind::Laplacian, CloudFamily::Centroids, true, 4, {16, 32, 64});
  ASSERT_EQ(l.rows.size(), 15u);  // 5 methods x 3 levels, sph first
  ASSERT_EQ(l.rows[2].method, "sph");
  ASSERT_EQ(l.rows[2].n, 64);
  EXPECT_LT(l.rows[2].order_inf, 0.5);
  EXPECT_GE(l.fitted_order_inf.at("vrsph"), 1.8);
}
