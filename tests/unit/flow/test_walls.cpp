// SPDX-License-Identifier: BSD-3-Clause
// Walls in the flow layer (docs/flow.md, "Walls"): the pressure equation with Neumann rows at the
// walls and its left null vector, the projection that keeps the walls' velocity, a closed box at
// rest under gravity that stays at rest (the wall condition balances the body force), the
// refusals, the moving least-squares sampling and the reference table of the cavity.
#include <cmath>
#include <numbers>
#include <Eigen/Dense>
#include <vrsph/analysis/point_sampling.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/cavity.hpp>
#include <vrsph/flow/ghia.hpp>
#include <vrsph/flow/projection.hpp>
#include <vrsph/flow/shifting.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

constexpr Real kPi = std::numbers::pi;

Operators box_ops(const PointCloud& cloud, const std::string& flux = "") {
  FlowOptions o;
  if (!flux.empty()) o.operators.method_options.set("flux", flux);
  return Operators(cloud, flow_operators(o));
}

// max |eig| of the projection w -> w - G φ over the fluid particles' velocities (the walls' held
// at zero), dense.
Real projection_radius(const Operators& ops, const PressureEquation& eq) {
  const PressurePoisson ppe = pressure_poisson(eq.matrix, eq.walls, eq.wall_flux, {});
  std::vector<Index> fluid;
  for (Index i = 0; i < ops.cloud().size(); ++i)
    if (!eq.walls.is_wall[static_cast<std::size_t>(i)]) fluid.push_back(i);
  const auto m = static_cast<Index>(fluid.size());
  Eigen::MatrixXd P(2 * m, 2 * m);
  for (Index k = 0; k < 2 * m; ++k) {
    Eigen::MatrixXd w = Eigen::MatrixXd::Zero(ops.cloud().size(), 2);
    w(fluid[static_cast<std::size_t>(k % m)], k / m) = 1;
    const Projected p = project(ops, ppe, w, {}, &eq);
    for (Index r = 0; r < 2 * m; ++r) P(r, k) = p.u(fluid[static_cast<std::size_t>(r % m)], r / m);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(P, false);
  return eigen.eigenvalues().cwiseAbs().maxCoeff();
}

// A potential with zero normal derivative on every face of the unit square, and its gradient.
Real box_potential(const Vec3& x) { return std::cos(kPi * x[0]) * std::cos(kPi * x[1]); }
Vec3 box_potential_gradient(const Vec3& x) {
  return {-kPi * std::sin(kPi * x[0]) * std::cos(kPi * x[1]), -kPi * std::cos(kPi * x[0]) * std::sin(kPi * x[1]), 0};
}
// A divergence-free velocity that vanishes on the walls: the curl of ψ = sin²πx sin²πy.
Vec3 box_vortex(const Vec3& x) {
  const Real sx = std::sin(kPi * x[0]), sy = std::sin(kPi * x[1]);
  const Real s2x = std::sin(2 * kPi * x[0]), s2y = std::sin(2 * kPi * x[1]);
  return {kPi * sx * sx * s2y, -kPi * s2x * sy * sy, 0};
}

// The smallest distance of a fluid particle to a face of the unit square.
Real closest_to_walls(const FlowSolver& s) {
  Real gap = 1;
  for (std::size_t i = 0; i < s.positions().size(); ++i) {
    if (s.walls().is_wall[i]) continue;
    const Vec3& x = s.positions()[i];
    gap = std::min({gap, x[0], 1 - x[0], x[1], 1 - x[1]});
  }
  return gap;
}

// A Lagrangian lid-driven cavity of three wall layers at nx = 16.
FlowSolver lagrangian_cavity(const PointCloud& c, FlowOptions o) {
  o.frame = FlowFrame::Lagrangian;
  o.wall_velocity = [](Index, const Vec3& x) { return cavity_lid_velocity(x); };
  return FlowSolver(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
}

Eigen::MatrixXd sample(const PointCloud& c, Vec3 (*f)(const Vec3&)) {
  Eigen::MatrixXd u(c.size(), 2);
  for (Index i = 0; i < c.size(); ++i) u.row(i) = f(c.positions[static_cast<std::size_t>(i)]).head(2).transpose();
  return u;
}

}  // namespace

TEST(FlowWalls, PressureRowsAnnihilateConstantsAndTheLeftNullVectorIsOne) {
  const PointCloud c = cavity_cloud({16, 0.2, 1});
  const Operators ops = box_ops(c);
  const Walls walls = walls_of(ops.cloud());
  EXPECT_EQ(walls.index.size(), 64u);  // 4 nx wall particles
  const PressureEquation eq = pressure_equation(ops, walls);
  ASSERT_EQ(eq.wall_flux.size(), static_cast<std::size_t>(c.size()));  // VRSPH: balance rows
  for (const Index i : walls.index) EXPECT_GT(eq.wall_flux[static_cast<std::size_t>(i)], 0);
  const CsrMatrix& A = eq.matrix;
  const Field ones = Field::Ones(c.size());
  EXPECT_LT((A * ones).cwiseAbs().maxCoeff(), 1e-9);
  const Field y = left_null_vector(A, {}, 20);
  EXPECT_NEAR(y[20], 1.0, 1e-9);
  EXPECT_GT(y.minCoeff(), 0);  // balance rows: the weights of a quadrature, all positive
  const Field yA = A.transpose() * y;
  EXPECT_LT(yA.cwiseAbs().maxCoeff(), 1e-8 * y.cwiseAbs().maxCoeff() * A.cwiseAbs().sum() / static_cast<Real>(c.size()));
}

TEST(FlowWalls, PressureSolveRecoversACompatiblePotential) {
  // r = A φ is compatible: the solve returns φ (zero mean) whatever the Neumann rows' scaling.
  const PointCloud c = cavity_cloud({16, 0.2, 1});
  const Operators ops = box_ops(c);
  const Walls walls = walls_of(ops.cloud());
  const PressureEquation eq = pressure_equation(ops, walls);
  const PressurePoisson ppe = pressure_poisson(eq.matrix, walls, eq.wall_flux, {});
  Field phi(c.size());
  for (Index i = 0; i < c.size(); ++i) phi[i] = box_potential(c.positions[static_cast<std::size_t>(i)]);
  phi.array() -= phi.mean();
  Field p;
  const PressurePoisson::Result r = ppe.solve(eq.matrix * phi, p);
  EXPECT_LT(std::abs(r.shift), 1e-9);
  EXPECT_LT((p - phi).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(FlowWalls, ProjectionRemovesTheGradientAndKeepsTheWalls) {
  // w = u + ∇φ with u divergence-free and zero on the walls, ∂φ/∂n = 0: the projection returns
  // u at the fluid particles (to the operators' error) and leaves the walls' values alone.
  Real previous = 0;
  for (const int nx : {16, 32}) {
    const PointCloud c = cavity_cloud({nx, 0.2, 2});
    const Operators ops = box_ops(c);
    const Walls walls = walls_of(ops.cloud());
    const PressureEquation eq = pressure_equation(ops, walls);
    const PressurePoisson ppe = pressure_poisson(eq.matrix, walls, eq.wall_flux, {});
    const Eigen::MatrixXd u = sample(c, box_vortex);
    const Eigen::MatrixXd w = u + sample(c, box_potential_gradient);
    const Projected p = project(ops, ppe, w, {}, &eq);
    Real error = 0;
    for (Index i = 0; i < c.size(); ++i) {
      if (walls.is_wall[static_cast<std::size_t>(i)]) {
        EXPECT_EQ(p.u.row(i), w.row(i));
      } else {
        error = std::max(error, (p.u.row(i) - u.row(i)).norm());
      }
    }
    EXPECT_LT(error, nx == 16 ? 0.5 : 0.15) << "nx = " << nx;
    if (previous > 0) {
      EXPECT_LT(error, 0.4 * previous) << "second order: a factor 4 per halving";
    }
    previous = error;
  }
}

TEST(FlowWalls, BalanceRowsKeepTheProjectionStableGradientRowsDoNot) {
  // A tangential mode of the first fluid layer grows under the projection with gradient rows
  // n·G at the walls (measured ρ = 1.146 at nx = 20, 1.52 on the nx = 24 lattice); VRSPH's
  // balance rows keep it at 1 (measured 1.00006).
  const PointCloud c = cavity_cloud({20, 0.2, 1});
  const Operators balance = box_ops(c);
  const Real stable = projection_radius(balance, pressure_equation(balance, walls_of(balance.cloud())));
  EXPECT_LT(stable, 1.001);
  const Operators gradient = box_ops(c, "gradient");
  const PressureEquation eq = pressure_equation(gradient, walls_of(gradient.cloud()));
  EXPECT_TRUE(eq.wall_flux.empty());
  EXPECT_GT(projection_radius(gradient, eq), 1.1);
}

TEST(FlowWalls, ABoxAtRestUnderGravityStaysAtRest) {
  // The walls' pressure rows n·G p = n·g balance gravity: no flow starts. FPM's gradient is exact
  // on the linear pressure, VRSPH's Laplacian nearly so: a few rows next to the walls miss their
  // moment conditions (NNLS residual up to 0.015 at nx = 16, |L y| up to 1.2e-4), which leaves a
  // spurious velocity of 2.5e-6 after 20 steps (measured).
  const PointCloud c = cavity_cloud({16, 0.2, 1});
  FlowOptions o;
  o.body_force = Vec3(0, -9.81, 0);
  FlowSolver s(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  for (int k = 0; k < 20; ++k) s.step(0.5 * s.stable_time_step());
  EXPECT_LT(s.velocity().cwiseAbs().maxCoeff(), 1e-5);
  const Field p = s.pressure();
  // p = -g y + const: its gradient is g at every particle.
  const Eigen::MatrixXd gp = s.operators().apply(OperatorKind::Gradient, p);
  EXPECT_LT((gp.col(1).array() + 9.81).abs().maxCoeff(), 1e-3);
  EXPECT_LT(gp.col(0).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(FlowWalls, ThreeDimensionalBoxesAtRestAndDriven) {
  // The same walls in 3D: a closed cube under gravity stays at rest (measured 5.5e-6 after 10
  // steps at n = 10), and a lid-driven cube runs stably (to t = 15 at n = 10, measured).
  PointCloud c = vertex_lattice(Domain::unit_box(3), 8);
  perturb(c, {.delta = 0.2, .seed = 1});
  FlowOptions still;
  still.body_force = Vec3(0, 0, -9.81);
  FlowSolver s(c, Eigen::MatrixXd::Zero(c.size(), 3), still);
  for (int k = 0; k < 10; ++k) s.step(0.5 * s.stable_time_step());
  EXPECT_LT(s.velocity().cwiseAbs().maxCoeff(), 1e-4);
  FlowOptions lid;
  lid.wall_velocity = [](Index, const Vec3& x) {
    const bool top = x[2] > 1 - 1e-12 && x[0] > 1e-12 && x[0] < 1 - 1e-12 && x[1] > 1e-12 && x[1] < 1 - 1e-12;
    return top ? Vec3(1, 0, 0) : Vec3::Zero();
  };
  FlowSolver d(c, Eigen::MatrixXd::Zero(c.size(), 3), lid);
  for (int k = 0; k < 20; ++k) d.step(0.9 * d.stable_time_step());
  EXPECT_GT(d.last().kinetic_energy, 0);
  EXPECT_LE(d.last().max_speed, 1.0 + 1e-12);
}

TEST(FlowWalls, ExtraWallLayersLieOutsideTheSquareAndKeepTheFluidsJitter) {
  const int n = 16;
  const PointCloud one = cavity_cloud({n, 0.2, 1});
  const PointCloud three = cavity_cloud({n, 0.2, 1, 3});
  ASSERT_EQ(three.size(), (n + 5) * (n + 5));
  EXPECT_EQ(one.size(), (n + 1) * (n + 1));
  for (Index i = 0; i < three.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Vec3& x = three.positions[k];
    if (i < one.size()) {
      EXPECT_EQ(x, one.positions[k]);  // the same lattice, the same jitter
      EXPECT_EQ(three.tags[k], one.tags[k]);
      continue;
    }
    EXPECT_EQ(three.tags[k], Tag::Dirichlet);
    EXPECT_NEAR(three.normals[k].norm(), 1.0, 1e-12);
    EXPECT_TRUE(x[0] < 0 || x[0] > 1 || x[1] < 0 || x[1] > 1) << "particle " << i << " inside the square";
    // The normal points away from the square: along it the particle is farther out.
    const Vec3 centre(0.5, 0.5, 0);
    EXPECT_GT((x - centre).dot(three.normals[k]), 0.5);
  }
  // The lid's outer layers slide with it; beyond the corners they rest.
  EXPECT_EQ(cavity_lid_velocity(Vec3(0.5, 1 + 2.0 / n, 0)), Vec3(1, 0, 0));
  EXPECT_EQ(cavity_lid_velocity(Vec3(-1.0 / n, 1 + 1.0 / n, 0)), Vec3::Zero());
  EXPECT_THROW_MSG(cavity_cloud({n, 0.2, 1, 9}), ConfigError, "wall layers");
}

TEST(FlowWalls, LagrangianWallsTakeExtrapolatedRowsAndHoldAColumnAtRest) {
  // In the Lagrangian frame the walls' pressure rows extrapolate the fluid's (Adami et al.
  // 2012), which is exact for the hydrostatic pressure: a closed box under gravity stays at rest
  // and its particles where they were.
  const PointCloud c = cavity_cloud({16, 0.2, 1, 3});
  FlowOptions o;
  o.frame = FlowFrame::Lagrangian;
  o.body_force = Vec3(0, -9.81, 0);
  FlowSolver s(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  EXPECT_EQ(s.options().support_growth, 1);  // walls: the supports do not grow by default
  for (int k = 0; k < 20; ++k) s.step(0.5 * s.stable_time_step());
  Real moved = 0;
  for (Index i = 0; i < c.size(); ++i)
    moved = std::max(moved, (s.positions()[static_cast<std::size_t>(i)] - c.positions[static_cast<std::size_t>(i)]).norm());
  EXPECT_LT(s.velocity().cwiseAbs().maxCoeff(), 1e-12);  // measured 1.7e-15 (balance rows, Eulerian: 2.5e-6)
  EXPECT_LT(moved, 1e-12);
  const Field p = s.pressure();
  const Eigen::MatrixXd gp = s.operators().apply(OperatorKind::Gradient, p);
  Real error = 0;
  for (Index i = 0; i < c.size(); ++i)
    if (!s.walls().is_wall[static_cast<std::size_t>(i)]) error = std::max(error, std::abs(gp(i, 1) + 9.81) + std::abs(gp(i, 0)));
  EXPECT_LT(error, 1e-10);  // measured 7e-14
  // Every row of the equation (fluid and walls, the dry outer corners too) annihilates constants.
  const PressureEquation eq =
      extrapolated_pressure_equation(s.operators(), s.walls(), std::vector<char>());
  EXPECT_TRUE(eq.surface.empty());
  const Field ones = Field::Ones(c.size());
  EXPECT_LT((eq.matrix * ones).cwiseAbs().maxCoeff(), 1e-8 * eq.matrix.coeffs().cwiseAbs().maxCoeff());
}

TEST(FlowWalls, TheLagrangianCavityKeepsItsWaterOffTheWalls) {
  // The lid-driven cavity with moving particles (Xu shifting, three wall layers): with balance
  // rows the particle next to the lid's downstream corner was flung off within 25 steps; with
  // extrapolated rows the water keeps off every wall (0.67 dx at the closest over these 64
  // steps, measured) and nothing outruns the lid.
  const int n = 16;
  FlowOptions o;
  o.nu = 0.01;
  o.shifting.kind = Shifting::Xu;
  FlowSolver s = lagrangian_cavity(cavity_cloud({n, 0.2, 1, 3}), o);
  Real gap = 1;
  for (int k = 0; k < 64; ++k) {
    s.step(0.25 / n);
    gap = std::min(gap, closest_to_walls(s));
  }
  EXPECT_GT(gap * n, 0.4);
  EXPECT_EQ(s.last().wall_pushes, 0);  // no wall gap asked for
  EXPECT_LE(s.last().max_speed, 1.0 + 1e-9);
  EXPECT_GT(s.last().kinetic_energy, 0.02);  // the lid has set the water turning
}

TEST(FlowWalls, TheWallGapReflectsParticlesOffTheWalls) {
  // FlowOptions::wall_gap: no fluid particle ends a step closer to a wall face than the gap. At
  // 0.9 dx the jittered first layer (0.8 dx at the closest) is reflected at once, counted.
  const int n = 16;
  const PointCloud c = cavity_cloud({n, 0.2, 1, 3});
  FlowOptions o;
  o.wall_gap = 0.9;
  FlowSolver s = lagrangian_cavity(c, o);
  Index pushes = 0;
  for (int k = 0; k < 8; ++k) {
    s.step(0.25 / n);
    pushes += s.last().wall_pushes;
    EXPECT_GE(closest_to_walls(s) * n, 0.9 - 1e-9) << "step " << k;
  }
  EXPECT_GT(pushes, 10);
  o.wall_gap = 1;
  EXPECT_THROW_MSG(lagrangian_cavity(c, o), ConfigError, "wall gap");
}

TEST(FlowWalls, TheLidDrivesTheFlowAndTheWallsKeepTheirVelocity) {
  const PointCloud c = cavity_cloud({16, 0.2, 1});
  FlowOptions o;
  o.wall_velocity = [](Index, const Vec3& x) { return cavity_lid_velocity(x); };
  FlowSolver s(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  for (int k = 0; k < 10; ++k) s.step(0.9 * s.stable_time_step());
  const Walls& walls = s.walls();
  Real fluid = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3 expected = cavity_lid_velocity(c.positions[static_cast<std::size_t>(i)]);
    if (walls.is_wall[static_cast<std::size_t>(i)])
      EXPECT_EQ(s.velocity().row(i), expected.head(2).transpose());
    else
      fluid = std::max(fluid, s.velocity().row(i).norm());
  }
  EXPECT_GT(fluid, 0.05);  // the lid has set the fluid moving
  EXPECT_LT(fluid, 1.0);   // and nothing outruns it
}

TEST(FlowWalls, RefusesWhatItCannotRun) {
  const PointCloud c = cavity_cloud({8, 0.2, 1});
  const Eigen::MatrixXd u = Eigen::MatrixXd::Zero(c.size(), 2);
  FlowOptions o;
  o.wall_velocity = [](Index, const Vec3&) { return Vec3(0, 1, 0); };  // through the floor and the lid
  EXPECT_THROW_MSG(FlowSolver(c, u, o), InputError, "moves through the wall");
  PointCloud no_normals = c;
  no_normals.normals.clear();
  EXPECT_THROW_MSG(FlowSolver(no_normals, u, {}), InputError, "has no normal");
  PointCloud neumann = c;
  neumann.tags[0] = Tag::Neumann;
  EXPECT_THROW_MSG(FlowSolver(neumann, u, {}), ConfigError, "tagged neumann");
  PointCloud no_walls = c;
  for (Tag& t : no_walls.tags) t = Tag::Interior;
  EXPECT_THROW_MSG(FlowSolver(no_walls, u, {}), ConfigError, "needs wall particles");
  CavityRunOptions run;
  run.re = 400;
  EXPECT_THROW_MSG(run_cavity(run), ConfigError, "Re = 100 and 1000");
}

TEST(PointSampling, IsExactOnQuadraticsAndNamesAStarvedPoint) {
  const PointCloud c = cavity_cloud({16, 0.3, 5});
  Eigen::MatrixXd f(c.size(), 2);
  const auto q = [](const Vec3& x) { return 1 + 2 * x[0] - x[1] + 3 * x[0] * x[1] - x[0] * x[0] + 0.5 * x[1] * x[1]; };
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& x = c.positions[static_cast<std::size_t>(i)];
    f(i, 0) = q(x);
    f(i, 1) = x[0];
  }
  const std::vector<Vec3> at = {{0.5, 0.5, 0}, {0.0, 0.0, 0}, {1.0, 0.37, 0}, {0.123, 0.987, 0}};
  const Eigen::MatrixXd s = sample_field(c, f, at, 2.5 / 16);
  for (std::size_t k = 0; k < at.size(); ++k) {
    EXPECT_NEAR(s(static_cast<Index>(k), 0), q(at[k]), 1e-11);
    EXPECT_NEAR(s(static_cast<Index>(k), 1), at[k][0], 1e-12);
  }
  const std::vector<Vec3> far = {{5, 5, 0}};
  EXPECT_THROW_MSG(sample_field(c, f, far, 0.1), GeometryError, "point 0 (5, 5) has 0 particles");
}

TEST(PointSampling, ReadsAcrossPeriodicFaces) {
  PointCloud c = cavity_cloud({16, 0.0, 1});
  c.domain.set_periodic("x");
  Eigen::MatrixXd f(c.size(), 1);
  for (Index i = 0; i < c.size(); ++i) f(i, 0) = std::cos(2 * kPi * c.positions[static_cast<std::size_t>(i)][0]);
  const std::vector<Vec3> at = {{0.999, 0.5, 0}};
  EXPECT_NEAR(sample_field(c, f, at, 2.5 / 16)(0, 0), std::cos(2 * kPi * 0.999), 5e-3);
}

TEST(Ghia, TablesForRe100And1000) {
  const GhiaProfiles& a = ghia_profiles(100);
  ASSERT_EQ(a.y.size(), 17u);
  ASSERT_EQ(a.u.size(), 17u);
  ASSERT_EQ(a.x.size(), 17u);
  ASSERT_EQ(a.v.size(), 17u);
  EXPECT_DOUBLE_EQ(a.u.front(), 1.0);  // the lid
  EXPECT_DOUBLE_EQ(a.u[9], -0.21090);  // the minimum at y = 0.4531
  EXPECT_DOUBLE_EQ(ghia_profiles(1000).v[5], -0.51550);
  for (const Real re : {100.0, 1000.0}) {
    const GhiaProfiles& g = ghia_profiles(re);
    ASSERT_EQ(g.u_converged.size(), 17u);
    ASSERT_EQ(g.v_converged.size(), 17u);
    Real u = 0, v = 0;  // the table's own distance from the converged solution (ghia.hpp)
    for (std::size_t k = 1; k + 1 < 17; ++k) {
      u = std::max(u, std::abs(g.u[k] - g.u_converged[k]));
      v = std::max(v, std::abs(g.v[k] - g.v_converged[k]));
    }
    EXPECT_NEAR(u, re == 100 ? 5.04e-3 : 6.30e-3, 1e-4);
    EXPECT_NEAR(v, re == 100 ? 9.24e-3 : 1.85e-2, 1e-4);
  }
  EXPECT_THROW_MSG(ghia_profiles(3200), ConfigError, "not 3200");
}
