// SPDX-License-Identifier: BSD-3-Clause
// The lid-driven cavity against Ghia, Ghia & Shin (1982) (cavity.hpp).
#include <cmath>
#include <vrsph/analysis/point_sampling.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/cavity.hpp>
#include <vrsph/flow/ghia.hpp>
#include "study_step.hpp"

namespace vrsph {

namespace {
// The largest deviation from the table over its points strictly inside (0, 1).
Real max_deviation(const std::vector<Real>& at, const std::vector<Real>& sampled, const std::vector<Real>& table) {
  Real m = 0;
  for (std::size_t k = 0; k < at.size(); ++k)
    if (at[k] > 0 && at[k] < 1) m = std::max(m, std::abs(sampled[k] - table[k]));
  return m;
}

// u (component 0) on x = 0.5 at heights `ys`, and v (component 1) on y = 0.5 at abscissae `xs`.
void centre_lines(const FlowSolver& solver, Real radius, const std::vector<Real>& ys, const std::vector<Real>& xs,
                  std::vector<Real>& u, std::vector<Real>& v) {
  std::vector<Vec3> pu, pv;
  for (const Real y : ys) pu.emplace_back(0.5, y, 0);
  for (const Real x : xs) pv.emplace_back(x, 0.5, 0);
  const PointCloud& cloud = solver.operators().cloud();
  const Eigen::MatrixXd su = sample_field(cloud, solver.velocity(), pu, radius);
  const Eigen::MatrixXd sv = sample_field(cloud, solver.velocity(), pv, radius);
  u.assign(su.col(0).data(), su.col(0).data() + su.rows());
  v.assign(sv.col(1).data(), sv.col(1).data() + sv.rows());
}
}  // namespace

PointCloud cavity_cloud(const CavityCloudSpec& spec) {
  check<ConfigError>(spec.nx >= 8 && spec.nx <= 4096, "cavity cloud: nx (intervals per side) must be in [8, 4096], got ",
                     spec.nx);
  check<ConfigError>(std::isfinite(spec.jitter) && spec.jitter >= 0 && spec.jitter < 0.5,
                     "cavity cloud: the jitter must be in [0, 0.5) particle spacings, got ", spec.jitter);
  PointCloud cloud = vertex_lattice(Domain::unit_box(2), spec.nx);
  if (spec.jitter > 0) {
    PerturbOptions p;
    p.delta = spec.jitter;
    p.seed = spec.seed;
    perturb(cloud, p);
  }
  return cloud;
}

Vec3 cavity_lid_velocity(const Vec3& x) {
  constexpr Real tol = 1e-12;
  return x[1] >= 1 - tol && x[0] > tol && x[0] < 1 - tol ? Vec3(1, 0, 0) : Vec3::Zero();
}

CavityRunRow run_cavity(const CavityRunOptions& o) {
  const GhiaProfiles& ghia = ghia_profiles(o.re);
  check<ConfigError>(std::isfinite(o.t_end) && o.t_end > 0, "cavity: the end time must be positive, got ", o.t_end);
  check<ConfigError>(std::isfinite(o.cfl) && o.cfl > 0 && o.cfl <= 2, "cavity: the CFL number must be in (0, 2], got ",
                     o.cfl);
  check<ConfigError>(std::isfinite(o.dt) && o.dt >= 0, "cavity: the time step must be finite and >= 0, got ", o.dt);
  check<ConfigError>(std::isfinite(o.steady_tolerance) && o.steady_tolerance > 0,
                     "cavity: the steady tolerance must be positive, got ", o.steady_tolerance);
  check<ConfigError>(o.flow.frame == FlowFrame::Eulerian, "cavity: the lagrangian cavity is not implemented (the fluid "
                     "particle at the lid's corner blows up: docs/flow.md)");
  const Stopwatch setup;
  PointCloud cloud = cavity_cloud(o.cloud);
  FlowOptions fo = o.flow;
  fo.nu = 1 / o.re;
  fo.wall_velocity = [](Index, const Vec3& x) { return cavity_lid_velocity(x); };
  const Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(cloud.size(), 2);
  FlowSolver solver(std::move(cloud), u0, fo);
  CavityRunRow row;
  row.seconds_setup = setup.seconds();
  row.nx = o.cloud.nx;
  row.re = o.re;
  row.particles = static_cast<Index>(solver.positions().size());
  const Real dx = solver.operators().spacing();
  const Real dt_target = o.dt > 0 ? o.dt : o.cfl * dx;
  detail::check_study_length("cavity", o.t_end, dt_target);
  row.dt = dt_target;
  const Stopwatch watch;
  detail::StepCosts costs;
  const std::vector<char>& wall = solver.walls().is_wall;
  while (solver.time() < o.t_end * (1 - 1e-12)) {
    const Real dt = detail::next_study_step(solver, "cavity", o.dt, dt_target, o.t_end, costs.steps, row.dt,
                                            "more particles, a hyperviscosity or a smaller --cfl");
    const Eigen::MatrixXd before = solver.velocity();
    costs.add(solver.step(dt));
    row.dt = std::min(row.dt, dt);
    Real change = 0;
    for (Index i = 0; i < before.rows(); ++i)
      if (!wall[static_cast<std::size_t>(i)]) change = std::max(change, (solver.velocity().row(i) - before.row(i)).norm());
    row.steady_residual = change / dt;
    if (o.on_step) o.on_step(solver, row.steady_residual);
    if (row.steady_residual < o.steady_tolerance) {
      row.steady = true;
      break;
    }
  }
  costs.write(row, watch.seconds());
  row.t = solver.time();
  row.max_div_u = solver.last().max_div_u;
  row.kinetic_energy = solver.last().kinetic_energy;
  // Profiles from a quadratic moving least-squares fit over 2.5 dx: its error is far below the
  // deviations measured (docs/flow.md).
  const Real radius = 2.5 * dx;
  centre_lines(solver, radius, ghia.y, ghia.x, row.u_at_ghia, row.v_at_ghia);
  row.ghia_max_deviation_u = max_deviation(ghia.y, row.u_at_ghia, ghia.u);
  row.ghia_max_deviation_v = max_deviation(ghia.x, row.v_at_ghia, ghia.v);
  row.reference_max_deviation_u = max_deviation(ghia.y, row.u_at_ghia, ghia.u_converged);
  row.reference_max_deviation_v = max_deviation(ghia.x, row.v_at_ghia, ghia.v_converged);
  for (int k = 0; k <= 100; ++k) row.line.push_back(k / 100.0);
  centre_lines(solver, radius, row.line, row.line, row.u_line, row.v_line);
  return row;
}

}  // namespace vrsph
