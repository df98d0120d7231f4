// SPDX-License-Identifier: BSD-3-Clause
// VRSPH boundary value problems beyond [QW]'s published cases (seed 000): the 3D
// analogue of Example 5, inhomogeneous Dirichlet data, the disk domain, and the
// near-boundary behaviour of the operator on perturbed particles. Bands: order >= 1.8.
#include <cmath>
#include <iostream>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/analysis/operator_study.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
void expect_orders(const BvpStudyResult& r, double band, const std::string& what) {
  std::cout << to_markdown(to_table(r));
  for (const auto& row : r.rows) {
    EXPECT_TRUE(row.m_matrix_all) << what << " n=" << row.first.n;
    if (row.first.n != r.params.n.front()) {
      EXPECT_GE(row.order_inf, band) << what << " n=" << row.first.n;
    }
  }
}
}  // namespace

TEST(VrsphBvp, Example5In3DOnPerturbedParticles) {
  BvpStudyParams p;
  p.dim = 3;
  p.cloud = CloudFamily::Perturbed;
  p.n = {8, 16, 24};
  p.solver.type = auto_direct_solver();  // UMFPACK, or SparseLU without SuiteSparse
  expect_orders(run_bvp_study(p), 1.8, "3D qw-ex5");
}

TEST(VrsphBvp, InhomogeneousDirichletDataOnPerturbedParticles) {
  BvpStudyParams p;
  p.problem = "custom";
  p.u = "exp(x)*sin(2*y) + x^2";
  p.a = "1 + x*y";
  p.cloud = CloudFamily::Perturbed;
  p.n = {20, 40, 80, 160};
  p.seeds = {3};
  expect_orders(run_bvp_study(p), 1.8, "inhomogeneous Dirichlet");
}

// The harmonic pair coefficient (methods/pair_mean.hpp), meant for jumps of a, keeps
// second order for a smooth, strongly varying a (it differs from a_i + a_j by O(r²)), and
// the M-matrix structure.
TEST(VrsphBvp, HarmonicPairMeanKeepsSecondOrderForSmoothCoefficients) {
  BvpStudyParams p;
  p.problem = "custom";
  p.u = "exp(x)*sin(2*y) + x^2";
  p.a = "exp(3*x - 2*y)";
  p.cloud = CloudFamily::Perturbed;
  p.n = {20, 40, 80};
  p.methods = {"vrsph", "sph"};
  p.method_options["vrsph"].set("mean", "harmonic");
  p.method_options["sph"].set("mean", "harmonic");
  const BvpStudyResult r = run_bvp_study(p);
  std::cout << to_markdown(to_table(r));
  for (const auto& row : r.rows) {
    EXPECT_TRUE(row.m_matrix_all) << row.first.method << " n=" << row.first.n;
    if (row.first.method == "vrsph" && row.first.n != 20) {
      EXPECT_GE(row.order_inf, 1.8) << "n=" << row.first.n;
    }
  }
}

TEST(VrsphBvp, DiskDomain) {
  BvpStudyParams p;
  p.problem = "custom";
  p.u = "exp(x)*sin(2*y) + x^2";
  p.a = "1 + x*y";
  p.cloud = CloudFamily::Disk;
  p.n = {20, 40, 80, 160};
  expect_orders(run_bvp_study(p), 1.8, "disk");
}

// [QW] leaves open perturbed particles next to the boundary. Measured: the VRSPH
// Laplacian is only about first order there (one-sided normal moments are infeasible
// for the particles nearest the wall), a larger h does not help, and keeping the first
// two layers regular in the normal direction restores second order.
TEST(VrsphBvp, PerturbedNearBoundaryOperatorAndItsRemedy) {
  OperatorStudyParams p;
  p.methods = {"vrsph"};
  p.op = OperatorKind::Laplacian;
  p.cloud = CloudFamily::Perturbed;
  p.ghosts = false;
  p.n = {32, 64, 128};
  const auto plain = run_operator_study(p);
  std::cout << to_markdown(to_table(plain));
  EXPECT_GT(plain.rows.back().infeasible, 0);
  const double plain_order = std::log(plain.rows.front().errors.near_boundary.linf / plain.rows.back().errors.near_boundary.linf) / std::log(4.0);
  EXPECT_LT(plain_order, 1.6);
  p.regular_layer = 2.5;
  const auto fixed = run_operator_study(p);
  std::cout << to_markdown(to_table(fixed));
  EXPECT_EQ(fixed.rows.back().infeasible, 0);
  const double fixed_order = std::log(fixed.rows.front().errors.near_boundary.linf / fixed.rows.back().errors.near_boundary.linf) / std::log(4.0);
  EXPECT_GE(fixed_order, 1.8);
}
