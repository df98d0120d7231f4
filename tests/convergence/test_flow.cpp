// SPDX-License-Identifier: BSD-3-Clause
// The flow layer against exact solutions (docs/flow.md): the frozen-cloud projection converges
// at second order with VRSPH's Laplacian while classic SPH's stalls; the Taylor–Green vortex in
// both frames converges, and its pressure at second order. Sizes kept small for CI; the long runs
// are documented commands. The lid-driven cavity at Re = 100 meets Ghia et al.'s profiles within a band.
#include <algorithm>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/flow/cavity.hpp>
#include <vrsph/flow/flow_study.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

std::vector<Real> sizes(const std::vector<int>& nx) {
  std::vector<Real> h;
  for (const int n : nx) h.push_back(1.0 / n);
  return h;
}

ProjectionStudyRow frozen(int nx, const std::string& method) {
  FlowCloudSpec spec;
  spec.nx = nx;
  FlowOptions fo;
  fo.operators.method = method;
  return frozen_projection(spec, flow_operators(fo), {});
}

VortexRunRow vortex(int nx, FlowFrame frame, Real t_end) {
  VortexRunOptions o;
  o.cloud.nx = nx;
  o.flow.frame = frame;
  o.t_end = t_end;
  return run_periodic_vortex(o);
}

}  // namespace

TEST(FlowConvergence, FrozenCloudProjectionIsSecondOrderWithVrsph) {
  const std::vector<int> nx{32, 64, 128};
  std::vector<Real> u_inf, phi;
  for (const int n : nx) {
    const ProjectionStudyRow r = frozen(n, "vrsph");
    u_inf.push_back(r.error_u_inf);
    phi.push_back(r.error_phi_inf);
    EXPECT_LT(r.max_div_after, 0.2 * r.max_div_before) << n;
  }
  const auto orders = pairwise_orders(sizes(nx), u_inf);
  EXPECT_GT(orders[1], 1.7);  // measured 1.77, 1.92 (docs/flow.md)
  EXPECT_GT(orders[2], 1.8);
  EXPECT_GT(least_squares_order(sizes(nx), phi), 1.8);
  // Classic SPH (Brookshaw Laplacian, SPH gradient) in the same setting does not converge.
  EXPECT_GT(frozen(128, "sph").error_u_inf, 20 * u_inf.back());
}

// The vortex at nx = 16, 32, 64 to t_end: mean velocity and pressure errors, and the runs.
struct Refinement {
  std::vector<int> nx{16, 32, 64};
  std::vector<Real> u_mean, p_mean;
  std::vector<VortexRunRow> runs;
};
Refinement refine(FlowFrame frame, Real t_end) {
  Refinement r;
  for (const int n : r.nx) {
    r.runs.push_back(vortex(n, frame, t_end));
    r.u_mean.push_back(r.runs.back().errors.error_u_mean);
    r.p_mean.push_back(r.runs.back().errors.error_p_mean);
  }
  return r;
}

TEST(FlowConvergence, TaylorGreenEulerianOnAPerturbedCloud) {
  const Refinement r = refine(FlowFrame::Eulerian, 0.1);
  for (const VortexRunRow& run : r.runs) EXPECT_LT(run.max_div_u, 1.0) << run.nx;
  // t = 0.1, early: the initial projection error dominates (measured: velocity 4.52e-3, 5.67e-4, 1.34e-4,
  // orders 3.0, 2.1; pressure 3.1e-3, 8.3e-3, 2.7e-3 — nx = 16 is below the trend by a cancellation —
  // and 7.1e-4 at nx = 128: orders 1.63, 1.92. Without the stage pressure's corrections the pressure
  // was 9.8e-2, 2.6e-2, 6.6e-3, orders 1.9, 2.0: larger at every nx.)
  EXPECT_GT(least_squares_order(sizes(r.nx), r.u_mean), 1.8);
  EXPECT_GT(pairwise_orders(sizes(r.nx), r.p_mean).back(), 1.5);
  EXPECT_LT(r.p_mean.back(), 3.5e-3);
  EXPECT_LT(r.u_mean.back(), 2e-4);
}

TEST(FlowConvergence, TaylorGreenEulerianDoesNotMoveWithTheTimeStepWithTheStagePressuresCorrected) {
  // The end-of-step projection removes the divergence each stage's rate leaves (L != D G), a
  // splitting whose error is O(dt dx^2); the stage pressure's defect correction makes the rate
  // divergence-free instead, and the result stops depending on dt. nx = 32, t = 1, error_u_mean
  // at CFL 0.25 / 0.125, measured: 4.90e-3 / 5.04e-3 corrected, 1.63e-3 / 3.29e-3 without
  // (where the splitting error cancelled part of the spatial one: docs/flow.md; the uncorrected
  // pair is left out to keep the suite short, the bound below fails it by a factor of eight).
  auto error = [](Real cfl, int corrections) {
    VortexRunOptions o;
    o.cloud.nx = 32;
    o.cfl = cfl;
    o.flow.pressure_corrections = corrections;
    return run_periodic_vortex(o).errors.error_u_mean;
  };
  const Real a = error(0.25, 1), b = error(0.125, 1);
  EXPECT_NEAR(a / b, 1.0, 0.06);
  EXPECT_LT(b, 6e-3);
}

TEST(FlowConvergence, TaylorGreenLagrangianShortRun) {
  const Refinement r = refine(FlowFrame::Lagrangian, 0.05);
  for (const VortexRunRow& run : r.runs) EXPECT_GT(run.min_spacing, 0.2) << run.nx;
  // Measured: velocity 5.55e-3, 3.42e-4, 4.84e-5; pressure 2.5e-3, 8.1e-3, 2.6e-3 (nx = 16 below the
  // trend, as in the Eulerian frame; without the stage pressure's corrections 9.9e-2, 2.6e-2, 6.6e-3).
  EXPECT_GT(least_squares_order(sizes(r.nx), r.u_mean), 1.8);
  EXPECT_GT(pairwise_orders(sizes(r.nx), r.p_mean).back(), 1.5);
  EXPECT_LT(r.p_mean.back(), 3.5e-3);
}

TEST(FlowConvergence, LidDrivenCavityMeetsGhiaWithinABandAtRe100) {
  // The steady cavity at Re = 100 on a perturbed cloud (jitter 0.2, nx = 32): the largest
  // centre-line deviation from Ghia et al.'s table within 0.03 (measured: u 1.14e-2, v 1.58e-2 with
  // the stage pressure's correction, 1.79e-2 and 2.49e-2 without; 5.5e-3 and 9.2e-3 at nx = 64,
  // docs/flow.md, where Ghia's own error is discussed).
  CavityRunOptions o;
  o.cloud.nx = 32;
  o.re = 100;
  o.t_end = 40;
  const CavityRunRow r = run_cavity(o);
  EXPECT_TRUE(r.steady) << "residual " << r.steady_residual;
  EXPECT_LT(r.t, 20) << "steady well before t = 20 (measured 13.8)";
  EXPECT_LT(r.ghia_max_deviation_u, 0.03);
  EXPECT_LT(r.ghia_max_deviation_v, 0.03);
  ASSERT_EQ(r.u_line.size(), 101u);
  EXPECT_NEAR(r.u_line.back(), 1.0, 0.01);  // the lid, through the fit
  EXPECT_NEAR(r.u_line.front(), 0.0, 0.01);
  // The primary vortex: u's minimum on the vertical centre line, Ghia's -0.2109 within 8 % (measured
  // -0.2223: the coarse cloud's vortex is too strong, docs/flow.md).
  EXPECT_NEAR(*std::min_element(r.u_line.begin(), r.u_line.end()), -0.2109, 0.08 * 0.2109);
}
