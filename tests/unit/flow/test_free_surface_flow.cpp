// SPDX-License-Identifier: BSD-3-Clause
// Free surfaces in the flow layer (docs/free_surface.md): the tank's cloud, the pressure equation
// with p = 0 rows at the surface and extrapolated wall rows, and the hydrostatic tank — water at rest
// under gravity in the Lagrangian frame, whose pressure must be g (H - y) and whose particles must
// stay at rest. VRSPH reproduces the linear hydrostatic pressure, so on a lattice the tank is at
// rest to round-off, and on a perturbed one (flat surface) to the solver's tolerance.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/tank.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

HydrostaticRow tank_run(int nx, Real jitter, const std::string& method = "vrsph", Real t_end = 2, int dim = 2,
                        Real wall_height = 0) {
  HydrostaticRunOptions o;
  o.tank.dim = dim;
  o.tank.wall_height = wall_height;
  o.tank.nx = nx;
  o.tank.jitter = jitter;
  o.flow.frame = FlowFrame::Lagrangian;
  o.flow.operators.method = method;
  o.t_end = t_end;
  return run_hydrostatic(o);
}

// The dam break as the CLI runs it (Lagrangian, Xu shifting), nx intervals across the column.
DamBreakRunOptions dam_break_options(int nx, Real t_star_end) {
  DamBreakRunOptions o;
  o.nx = nx;
  o.flow.frame = FlowFrame::Lagrangian;
  o.flow.shifting.kind = Shifting::Xu;
  o.t_star_end = t_star_end;
  return o;
}

// A tank at rest under full gravity (no time step taken): its cloud and solver.
struct StillTank {
  PointCloud cloud;
  FlowSolver solver;
};
StillTank still_tank(int nx, Real wall_height, Real jitter) {
  TankSpec s;
  s.nx = nx;
  s.wall_height = wall_height;
  s.jitter = jitter;
  PointCloud c = tank_cloud(s);
  FlowOptions o;
  o.free_surface = true;
  o.body_force = Vec3(0, -1, 0);
  FlowSolver solver(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  return {std::move(c), std::move(solver)};
}

Real max_speed(const Eigen::MatrixXd& u) { return u.rows() ? u.rowwise().norm().maxCoeff() : 0.0; }

}  // namespace

TEST(TankCloud, WallsNormalsWaterAndRefusals) {
  TankSpec s;
  s.nx = 10;
  s.wall_height = 1.2;
  const PointCloud c = tank_cloud(s);
  // Walls: the bottom (11) and two sides of 12 more particles each; water: 9 x 10 (the top row at y = 1).
  EXPECT_EQ(c.count(Tag::Dirichlet), 11 + 2 * 12);
  EXPECT_EQ(c.count(Tag::Interior), 9 * 10);
  Real top = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const auto iu = static_cast<std::size_t>(i);
    if (c.tags[iu] == Tag::Interior) top = std::max(top, c.positions[iu][1]);
    if (c.tags[iu] == Tag::Dirichlet) {
      EXPECT_NEAR(c.normals[iu].norm(), 1.0, 1e-14);
    }
  }
  EXPECT_DOUBLE_EQ(top, 1.0);
  EXPECT_EQ(c.normals[0], Vec3(-1, -1, 0).normalized());  // the corner's diagonal
  TankSpec thick = s;
  thick.wall_layers = 3;  // two more layers outside each face: i, j in [-2, 12], less the 9 x 12 inside
  const PointCloud t = tank_cloud(thick);
  EXPECT_EQ(t.count(Tag::Dirichlet), 15 * 15 - 9 * 12);
  EXPECT_EQ(t.count(Tag::Interior), 9 * 10);
  thick.wall_layers = 9;
  EXPECT_THROW_MSG(tank_cloud(thick), ConfigError, "wall layers must be in [1, 8]");
  s.column_width = 0.5;  // a dam break's column
  EXPECT_EQ(tank_cloud(s).count(Tag::Interior), 5 * 10);
  s.column_width = 1.5;
  EXPECT_THROW_MSG(tank_cloud(s), ConfigError, "does not fit the tank");
  s.column_width = 0;
  s.depth = 0.33;
  EXPECT_THROW_MSG(tank_cloud(s), ConfigError, "not a whole number of particle spacings");
  s.depth = 1;
  s.wall_height = 0.5;
  EXPECT_THROW_MSG(tank_cloud(s), ConfigError, "does not fit the tank");
}

TEST(FreeSurfaceFlow, PressureEquationIsExactForTheHydrostaticPressure) {
  const StillTank tank = still_tank(16, 1, 0.2);
  const PointCloud& c = tank.cloud;
  const FlowSolver& solver = tank.solver;
  EXPECT_EQ(solver.surface().count, 15);  // the top row, no wall
  const Field p = solver.pressure();
  const Eigen::MatrixXd gp = solver.operators().apply(OperatorKind::Gradient, p);
  Real error = 0, gradient = 0;
  for (Index i = 0; i < c.size(); ++i) {
    error = std::max(error, std::abs(p[i] - (1 - c.positions[static_cast<std::size_t>(i)][1])));
    if (c.tags[static_cast<std::size_t>(i)] == Tag::Interior) gradient = std::max(gradient, (gp.row(i) - Eigen::RowVector2d(0, -1)).norm());
  }
  EXPECT_LT(error, 1e-5);     // measured 7.7e-7: the residual of the rows' NNLS moment conditions
  EXPECT_LT(gradient, 1e-4);  // the least-squares gradient at the surface's corner particles (measured 3e-6)
}

TEST(FreeSurfaceFlow, ExtrapolatedWallRowsExtendThePressureAboveTheWaterAndGiveTheAirZero) {
  // Six wall particles above the water on each side, the top two in the air.
  const StillTank tank = still_tank(10, 1.6, 0.2);
  const PointCloud& c = tank.cloud;
  const FlowSolver& solver = tank.solver;
  const Field p = solver.pressure();
  const Real support = solver.operators().neighbours().radius(0);
  for (const Index w : solver.walls().index) {
    const Real y = c.positions[static_cast<std::size_t>(w)][1];
    if (y <= 1 + support - 0.05) {  // water in its support: the hydrostatic field, extended above the surface
      EXPECT_NEAR(p[w], 1 - y, 1e-4) << "wall " << w << " at y = " << y;
    } else if (y >= 1 + support + 0.05) {  // in the air
      EXPECT_EQ(p[w], 0.0) << "wall " << w << " at y = " << y;
    }
  }
}

TEST(FreeSurfaceFlow, HydrostaticTankStaysAtRestOnALattice) {
  const HydrostaticRow r = tank_run(10, 0.0);
  EXPECT_LT(r.bottom_pressure_error, 1e-12);
  EXPECT_LT(r.pressure_profile_error, 1e-12);
  EXPECT_LT(r.max_speed_after_ramp, 1e-12);
  EXPECT_EQ(r.surface_particles, 9);
  EXPECT_NEAR(r.t, 2.0, 1e-12);
}

// A run that ends within the ramp (T = 0.5) carries the weight of the gravity in force then,
// (1 - cos(π t / T)) / 2 of g: its error is measured against that, not against the full g H
// (which read 0.905 at t = 0.1 for a pressure exact to 1e-6).
TEST(FreeSurfaceFlow, HydrostaticTankEndingWithinTheRampIsComparedWithTheRampedWeight) {
  const HydrostaticRow row = tank_run(8, 0.0, "vrsph", 0.1);
  const Real fraction = 0.5 * (1 - std::cos(std::numbers::pi * row.t / 0.5));
  EXPECT_NEAR(row.bottom_pressure, fraction, 1e-9);  // a lattice: exact to round-off at any weight
  EXPECT_LT(row.bottom_pressure_error, 1e-9);
  EXPECT_LT(row.pressure_profile_error, 1e-9);
  ASSERT_FALSE(row.line_exact.empty());
  EXPECT_NEAR(row.line_exact.front(), fraction, 1e-12);  // g = H = 1
}

TEST(FreeSurfaceFlow, HydrostaticTankOnPerturbedParticlesConvergesAndStaysStill) {
  const HydrostaticRow coarse = tank_run(10, 0.2), fine = tank_run(20, 0.2);
  // Targets of the issue: bottom pressure within 1 % and spurious speed below 1e-3 (g H)^½.
  // Measured: 1.7e-5 and 1.1e-7 (bottom), 2.2e-6 and 1.9e-7 (speed) over t = 2.
  EXPECT_LT(coarse.bottom_pressure_error, 1e-3);
  EXPECT_LT(fine.bottom_pressure_error, coarse.bottom_pressure_error);
  EXPECT_LT(fine.max_speed_after_ramp, 1e-5);
  EXPECT_LT(fine.surface_rise, 0.01);
  EXPECT_LT(fine.surface_drop, 0.01);
  EXPECT_EQ(fine.surface_particles, 19);
}

// Over 20 s the coarsest tank's surface row grew a dt-independent, inviscid instability from the
// projection's one-sided quadratic gradient rows there (spurious speed e^{0.8 t}, 1.9e-2 at
// t = 20, two surface particles sunk by a third of a spacing). The linear fit at the surface
// particles (SurfaceGradient::Linear, the default) holds it: measured 2.7e-6 and a bottom error
// of 3.6e-5 at t = 20 (docs/free_surface.md).
TEST(FreeSurfaceFlow, CoarseTankStaysStillForTwentySecondsWithLinearSurfaceRows) {
  HydrostaticRunOptions o;
  o.tank.nx = 10;
  o.tank.jitter = 0.2;
  o.flow.frame = FlowFrame::Lagrangian;
  o.t_end = 20;
  EXPECT_EQ(flow_operators([&] { FlowOptions f = o.flow; f.free_surface = true; return f; }()).marked_gradient_method, "fpm");
  {  // the linear rows: at the surface particles without a wall neighbour (the walls fill a support's side)
    const StillTank tank = still_tank(10, 1.0, 0.2);
    const Operators& ops = tank.solver.operators();
    const std::vector<char>& marked = ops.marked_rows();
    ASSERT_EQ(static_cast<Index>(marked.size()), tank.cloud.size());
    Index count = 0;
    for (Index i = 0; i < tank.cloud.size(); ++i) {
      bool wall = false;
      for (const Index j : ops.neighbours().of(i)) wall = wall || tank.solver.walls().is_wall[static_cast<std::size_t>(j)];
      const bool surface = tank.solver.surface().surface[static_cast<std::size_t>(i)];
      EXPECT_EQ(marked[static_cast<std::size_t>(i)] != 0, surface && !wall) << i;
      count += marked[static_cast<std::size_t>(i)] != 0;
    }
    EXPECT_GT(count, 0);
    EXPECT_LT(count, tank.solver.surface().count);
  }
  const HydrostaticRow linear = run_hydrostatic(o);
  EXPECT_NEAR(linear.t, 20, 1e-9);
  EXPECT_LT(linear.max_speed_after_ramp, 1e-4);  // the target 1e-3 (g H)^½
  EXPECT_LT(linear.bottom_pressure_error, 1e-3);
  EXPECT_LT(linear.surface_drop, 0.01);
  EXPECT_EQ(linear.surface_particles, 9);
  o.flow.surface_gradient = SurfaceGradient::Same;  // the quadratic rows there too: the growth
  const HydrostaticRow same = run_hydrostatic(o);
  EXPECT_GT(same.max_speed_after_ramp, 1e-3);
  EXPECT_EQ(parse_surface_gradient("same"), SurfaceGradient::Same);
  EXPECT_EQ(to_string(SurfaceGradient::Linear), "linear");
  EXPECT_THROW_MSG(parse_surface_gradient("cubic"), ConfigError, "linear, same");
}

// A channel periodic along x with a free top and a floor of wall particles: water at rest under
// gravity. Its surface particles are far from the floor, so every one takes the linear rows, which
// the operators build on the periodic box; the water stays at rest.
TEST(FreeSurfaceFlow, PeriodicChannelStaysStillWithItsSurfaceOnLinearRows) {
  const int n = 20;
  const Real dx = 1.0 / n;
  PointCloud c;
  c.dim = 2;
  c.spacing = dx;
  for (int i = 0; i < n; ++i)
    for (int j = -2; j <= n / 2; ++j) {
      const bool wall = j <= 0;
      Vec3 x(i * dx, j * dx, 0);
      if (!wall && j < n / 2) x[0] += 0.2 * dx * std::sin(7.3 * i + 3.1 * j);  // jittered inside, a flat top row
      if (!wall && j < n / 2) x[1] += 0.2 * dx * std::cos(5.7 * i - 2.3 * j);
      c.positions.push_back(x);  // normals stored for every particle: the floor's are its walls'
      c.tags.push_back(wall ? Tag::Dirichlet : Tag::Interior);
      c.normals.push_back(wall ? Vec3(0, -1, 0) : Vec3::Zero());
    }
  c.domain = Domain::box(2, Vec3(0, -3 * dx, 0), Vec3(1, 1, 0));
  c.domain.set_periodic("x");
  for (auto& x : c.positions) x = c.domain.wrap(x);
  FlowOptions o;
  o.frame = FlowFrame::Lagrangian;
  o.free_surface = true;
  o.body_force = Vec3(0, -1, 0);
  o.body_force_ramp = 0.5;
  FlowSolver solver(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  EXPECT_EQ(solver.surface().count, n);
  const std::vector<char>& marked = solver.operators().marked_rows();
  EXPECT_EQ(std::count(marked.begin(), marked.end(), 1), n);  // the whole top row: no wall within reach
  while (solver.time() < 2 - 1e-12) solver.step(std::min(0.9 * solver.stable_time_step(), 2 - solver.time()));
  EXPECT_LT(max_speed(solver.velocity()), 1e-4);  // measured 1.6e-7 (g H)^½ at t = 2
  EXPECT_EQ(solver.surface().count, n);
}

TEST(FreeSurfaceFlow, ThreeDimensionalTank) {
  const HydrostaticRow r = tank_run(6, 0.2, "vrsph", 0.5, 3);
  EXPECT_LT(r.bottom_pressure_error, 2e-3);  // measured 3.3e-4 at t = 1
  EXPECT_LT(r.max_speed_after_ramp, 2e-3);
  EXPECT_EQ(r.surface_particles, 25);        // the 5 x 5 top layer
}

TEST(FreeSurfaceFlow, ThreeDimensionalTankWithWallsAboveTheWater) {
  // A wall particle above the water sees the wall's plane and the water's flat top row: a
  // singular quadratic fit, whose condition fell below the methods' limit of 1e12 once the water
  // had moved by ~1e-7 dx, and the run blew up at its fifth step (walls 2 dx higher) or ninth (4
  // dx). The flow's limit of 1e6 on free surfaces leaves those rows zero. Measured at t = 1 (docs):
  // bottom errors 2.5e-6 and 1.1e-6, speeds 1.5e-6 and 1.1e-6 (in (g H)^½); walls 2 dx higher to
  // t = 0.5 here (the blow-up came at t = 0.31), to keep the sanitizer stage short.
  const HydrostaticRow r = tank_run(6, 0.2, "vrsph", 0.5, 3, 1.0 + 2 / 6.0);
  EXPECT_NEAR(r.t, 0.5, 1e-12);
  EXPECT_LT(r.bottom_pressure_error, 1e-4);
  EXPECT_LT(r.max_speed, 1e-4);
}

TEST(FreeSurfaceFlow, WallsStayWhereTheyAreInTheLagrangianFrame) {
  TankSpec s;
  s.nx = 10;
  s.wall_height = 1;
  const PointCloud c = tank_cloud(s);
  FlowOptions o;
  o.frame = FlowFrame::Lagrangian;
  o.free_surface = true;
  o.body_force = Vec3(0, -1, 0);
  Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(c.size(), 2);
  for (Index i = 0; i < c.size(); ++i)
    if (c.tags[static_cast<std::size_t>(i)] == Tag::Interior) u0(i, 0) = 0.1 * std::sin(3 * c.positions[static_cast<std::size_t>(i)][1]);
  FlowSolver solver(c, u0, o);
  solver.step(0.5 * solver.stable_time_step());
  for (const Index i : solver.walls().index)
    EXPECT_EQ(solver.positions()[static_cast<std::size_t>(i)], c.positions[static_cast<std::size_t>(i)]);
  Real moved = 0;
  for (Index i = 0; i < c.size(); ++i) moved = std::max(moved, (solver.positions()[static_cast<std::size_t>(i)] - c.positions[static_cast<std::size_t>(i)]).norm());
  EXPECT_GT(moved, 0.0);
}

TEST(FreeSurfaceFlow, RefusesWhatCannotRunAndStopsALostParticle) {
  TankSpec s;
  s.nx = 10;
  const PointCloud c = tank_cloud(s);
  FlowOptions o;
  o.free_surface = true;
  EXPECT_THROW_MSG(FlowSolver(c, Eigen::MatrixXd::Zero(c.size(), 2), o), ConfigError, "nothing drives this flow");
  HydrostaticRunOptions h;
  h.tank.nx = 10;
  h.gravity = 0;
  EXPECT_THROW_MSG(run_hydrostatic(h), ConfigError, "the gravity must be positive");
  h.gravity = 1;
  h.tank.column_width = 0.5;
  EXPECT_THROW_MSG(run_hydrostatic(h), ConfigError, "a column is a dam break");
  h.tank.column_width = 0;
  o.body_force = Vec3(0, -1, 0);
  o.surface.density_threshold = 1.5;
  EXPECT_THROW_MSG(FlowSolver(c, Eigen::MatrixXd::Zero(c.size(), 2), o), ConfigError, "must lie in (0, 1)");
  // Classic SPH's gradient rows at the walls give a bottom pressure 74 % too high: the water is
  // pushed through the walls and the run stops at the step a particle leaves the tank.
  h.flow.frame = FlowFrame::Lagrangian;
  h.flow.operators.method = "sph";
  h.tank.jitter = 0.2;
  EXPECT_THROW_MSG(run_hydrostatic(h), NumericalError, "left the box");
  // A support of about one spacing: no VRSPH row meets its moment conditions and the pressure
  // matrix is singular. The solver's failure is said with its cause; a support of 1.45 dx (rows
  // that are mostly infeasible too, but a solvable matrix) runs.
  HydrostaticRunOptions narrow;
  narrow.tank.nx = 10;
  narrow.t_end = 0.05;
  narrow.tank.jitter = 0.2;  // as the CLI's default cloud: some particles then have no neighbour at all
  narrow.flow.frame = FlowFrame::Lagrangian;
  narrow.flow.operators.h_factor = 1.01;
  EXPECT_THROW_MSG(run_hydrostatic(narrow), ConfigError, "is too small for vrsph's Laplacian");
  narrow.flow.operators.h_factor = 1.45;
  EXPECT_NO_THROW(run_hydrostatic(narrow));
}

// Droplets: one particle 1.5 dx beside the left wall and one in the open air above the water,
// both far above it, with no viscosity. A free surface lets a particle stand alone (empty rows:
// it was a GeometryError), and the walls beside a detached droplet take the air's pressure: they
// used to extrapolate its p = 0 along g·(x_w - x_f), a hydrostatic column that held it still.
// Both must fall as in a vacuum, v = -g t.
TEST(FreeSurfaceFlow, DetachedDropletsFallFreelyBesideAWallAndInTheAir) {
  TankSpec s;
  s.nx = 10;
  s.wall_height = 3;
  PointCloud c = tank_cloud(s);
  const Real dx = c.spacing;
  const auto wall_droplet = static_cast<Index>(c.size());
  c.add(Vec3(1.5 * dx, 2.5, 0), Tag::Interior);
  const auto air_droplet = static_cast<Index>(c.size());
  c.add(Vec3(0.5, 2.5, 0), Tag::Interior);
  FlowOptions o;
  o.frame = FlowFrame::Lagrangian;
  o.free_surface = true;
  o.nu = 0;
  o.body_force = Vec3(0, -1, 0);
  FlowSolver solver(c, Eigen::MatrixXd::Zero(c.size(), 2), o);
  EXPECT_TRUE(solver.surface().surface[static_cast<std::size_t>(wall_droplet)]);
  EXPECT_TRUE(solver.surface().surface[static_cast<std::size_t>(air_droplet)]);
  EXPECT_EQ(solver.operators().neighbours().count(air_droplet), 0);
  const Field p = solver.pressure();
  for (const Index w : solver.walls().index) {
    if (c.positions[static_cast<std::size_t>(w)][1] > 2) {
      EXPECT_EQ(p[w], 0.0) << "wall " << w;  // beside the droplet
    }
  }
  for (int k = 0; k < 8; ++k) solver.step(0.02);
  for (const Index i : {wall_droplet, air_droplet}) {
    EXPECT_NEAR(solver.velocity()(i, 1), -solver.time(), 1e-12) << "droplet " << i;
    EXPECT_NEAR(solver.velocity()(i, 0), 0.0, 1e-12) << "droplet " << i;
    EXPECT_NEAR(solver.positions()[static_cast<std::size_t>(i)][1], 2.5 - 0.5 * solver.time() * solver.time(), 1e-12);
  }
}

// The impact on the far wall and the run-up along it. Before: the run stopped when the front
// reached the wall; run on, the run-up's tip was pumped to 8.6 (g L)^½ within 20 steps (the
// shift's velocity expansion at surface particles, and the wall's viscous term carried into its
// extrapolated pressure) and left the tank at T = 3.5–3.8 (nx = 10). With the walls carrying the
// body force only, the water rises along the wall, to T = 4.2 here (measured: to T = 11.3 on the
// lattice, 8.5 at nx = 10 and 20).
TEST(DamBreak, RunsThroughTheImpactOnTheFarWall) {
  DamBreakRunOptions o = dam_break_options(10, 4.2);
  o.flow.wall_acceleration = WallAcceleration::BodyForce;
  const DamBreakRun r = run_dam_break(o);
  EXPECT_TRUE(r.stopped.empty()) << r.stopped;
  EXPECT_NEAR(r.t_star, 4.2, 1e-9);
  EXPECT_TRUE(r.reached_far_wall);
  EXPECT_GT(r.far_wall_t_star, 3.0);  // measured 3.25 (nx = 10)
  EXPECT_LT(r.far_wall_t_star, 3.6);
  EXPECT_LT(r.max_outside_experiments, 0.25);
  Real fastest = 0;
  for (const DamBreakSample& s : r.samples) fastest = std::max(fastest, s.max_speed);
  // Measured 4.13 (the run-up on the far wall; 2.96 before the surface's linear gradient rows of
  // 2026-12-06, a chaotic quantity after the impact); the pumped jet reached 8.6 and left the tank.
  EXPECT_LT(fastest, 5.0);
  EXPECT_TRUE(std::isnan(r.samples.back().probe_pressure));  // the probe is Buchner's tank's
  // The residual column against Martin & Moyce's Table 6 before the far wall: measured 0.169
  // here, the column above theirs (docs/free_surface.md, "The residual column": the no-slip wall
  // at Re = 100 holds the water beside it up). A column that fell through the floor or stood
  // still would be 1-2 L away.
  EXPECT_TRUE(std::isfinite(r.max_height_deviation));
  EXPECT_LT(r.max_height_deviation, 0.3);
}

// Buchner's tank: its geometry, and the probe's reference record read back.
TEST(DamBreak, BuchnerTankAndItsProbeRecord) {
  EXPECT_EQ(parse_dam_break_geometry("buchner"), DamBreakGeometry::Buchner);
  EXPECT_EQ(to_string(parse_dam_break_geometry("martin-moyce")), "martin-moyce");
  EXPECT_THROW_MSG(parse_dam_break_geometry("lobovsky"), ConfigError, "martin-moyce | buchner");
  const SurgeCurve& ref = buchner_probe_reference();
  ASSERT_EQ(ref.t_star.size(), ref.z_over_l.size());
  for (std::size_t k = 1; k < ref.t_star.size(); ++k) EXPECT_GT(ref.t_star[k], ref.t_star[k - 1]);
  EXPECT_DOUBLE_EQ(ref.at(2.77411), 0.68698);  // the first peak
  DamBreakRunOptions o = dam_break_options(8, 0.3);
  o.geometry = DamBreakGeometry::Buchner;
  const DamBreakRun r = run_dam_break(o);
  EXPECT_TRUE(r.stopped.empty()) << r.stopped;
  EXPECT_EQ(r.water_particles, 16 * 8);  // 2H x H at H / 8, the floor and the left wall are walls
  EXPECT_NEAR(r.samples.front().front_z_over_l, 2.0, 1e-12);
  EXPECT_EQ(r.samples.front().probe_pressure, 0.0);  // no water at the far wall yet
  EXPECT_TRUE(std::isnan(r.samples.front().probe_reference));  // before Buchner's record starts
  EXPECT_TRUE(std::isnan(r.samples.front().experiment_low));   // the fronts' references are the other tank's
  EXPECT_TRUE(std::isnan(r.probe_peak));                        // the run ended before T = 3.5
}

TEST(DamBreak, ReferenceCurvesInterpolateAndStopAtTheirEnds) {
  const std::vector<SurgeCurve>& refs = dam_break_references();
  ASSERT_EQ(refs.size(), 3u);
  EXPECT_DOUBLE_EQ(refs[0].at(0.849), 1.245);
  EXPECT_NEAR(refs[1].at(0.5 * (1.997 + 2.547)), 0.5 * (2.292 + 2.995), 1e-12);
  EXPECT_TRUE(std::isnan(refs[0].at(0.5)));   // before Martin & Moyce's first point
  EXPECT_TRUE(std::isnan(refs[2].at(3.2)));   // after Koshizuka & Oka's last
  EXPECT_DOUBLE_EQ(refs[2].at(0.0), 1.0);
  // The column height: Martin & Moyce's (τ, H) in this tank's units, T = √2 τ, η/L = 2H.
  const SurgeCurve& height = martin_moyce_height_reference();
  EXPECT_NEAR(height.at(std::sqrt(2.0) * 0.56), 2 * 0.94, 1e-12);
  EXPECT_NEAR(height.at(std::sqrt(2.0) * 2.0), 2 * 0.50, 1e-12);
  EXPECT_TRUE(std::isnan(height.at(0.5)));  // before their first point
}

// Under gravity in a closed box a particle faster than twice a free fall across the box (times
// max_speed_growth) is a blow-up: the run stops there with its reason, not later with steps
// shortened towards zero. Here the bound is made tight enough (growth 0.05: 0.05 x 2 √(2 g D),
// D = 5 L the box's height) for the column's own fall to pass it within T = 0.5.
TEST(DamBreak, ParticleOutrunningAFreeFallAcrossTheBoxStopsTheRun) {
  DamBreakRunOptions o = dam_break_options(8, 0.5);
  o.flow.max_speed_growth = 0.05;
  const DamBreakRun tight = run_dam_break(o);
  EXPECT_NE(tight.stopped.find("twice the speed of a free fall across the box"), std::string::npos) << tight.stopped;
  EXPECT_LT(tight.t_star, 0.5);
  EXPECT_GT(tight.samples.back().max_speed, 0.0);
  o.flow.max_speed_growth = 0;  // the check off
  const DamBreakRun off = run_dam_break(o);
  EXPECT_TRUE(off.stopped.empty()) << off.stopped;
  EXPECT_NEAR(off.t_star, 0.5, 1e-9);
  o.flow.max_speed_growth = 1.5;  // the default: a falling column is far below it
  const DamBreakRun normal = run_dam_break(o);
  EXPECT_TRUE(normal.stopped.empty()) << normal.stopped;
}

TEST(DamBreak, SurgeFrontFollowsTheExperimentsOnACoarseColumn) {
  const DamBreakRunOptions o = dam_break_options(10, 2.0);
  const DamBreakRun r = run_dam_break(o);
  EXPECT_TRUE(r.stopped.empty()) << r.stopped;
  EXPECT_NEAR(r.t_star, 2.0, 1e-9);
  // Measured: the front 0.15 L ahead of both experiments at T = 1.25, within 0.01 L at T = 2
  // (Koshizuka & Oka's MPS is ahead of them too, by 0.1 L).
  EXPECT_LT(r.max_outside_experiments, 0.25);
  EXPECT_GT(r.samples.back().front_z_over_l, 2.2);
  Real front = 0, column = 3;
  for (const DamBreakSample& s : r.samples) {
    EXPECT_GE(s.front_z_over_l, front - 1e-3);        // the surge advances
    EXPECT_LE(s.column_height_over_l, column + 1e-3);  // the column falls
    front = s.front_z_over_l;
    column = s.column_height_over_l;
  }
  DamBreakRunOptions eulerian = o;
  eulerian.flow.frame = FlowFrame::Eulerian;
  EXPECT_THROW_MSG(run_dam_break(eulerian), ConfigError, "must be lagrangian");
}
