// SPDX-License-Identifier: BSD-3-Clause
// The tank's cloud and the hydrostatic tank (tank.hpp).
#include <cmath>
#include <vrsph/analysis/point_sampling.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/tank.hpp>
#include "study_step.hpp"

namespace vrsph {

namespace {
// length / dx as a whole number of spacings, or ConfigError naming the length.
int whole_spacings(Real length, Real dx, const char* what) {
  const Real k = length / dx;
  check<ConfigError>(std::abs(k - std::round(k)) <= 1e-9 * std::max<Real>(1, k) && std::round(k) >= 1, "tank: the ", what,
                     " (", length, ") is not a whole number of particle spacings (", dx, ")");
  return static_cast<int>(std::round(k));
}
}  // namespace

PointCloud tank_cloud(const TankSpec& s) {
  check<ConfigError>(s.dim == 2 || s.dim == 3, "tank: the dimension must be 2 or 3, got ", s.dim);
  check<ConfigError>(s.nx >= 4 && s.nx <= 4096, "tank: nx (intervals across the width) must be in [4, 4096], got ", s.nx);
  for (const Real v : {s.width, s.depth})
    check<ConfigError>(std::isfinite(v) && v > 0, "tank: the width and the depth must be positive, got ", s.width, " and ",
                       s.depth);
  check<ConfigError>(std::isfinite(s.column_width) && s.column_width >= 0 && s.column_width <= s.width,
                     "tank: the water column (width ", s.column_width, ") does not fit the tank (width ", s.width, ")");
  check<ConfigError>(std::isfinite(s.jitter) && s.jitter >= 0 && s.jitter < 0.5,
                     "tank: the jitter must be in [0, 0.5) particle spacings, got ", s.jitter);
  const Real dx = s.width / s.nx;
  const Real wall_height = s.wall_height > 0 ? s.wall_height : s.depth + 4 * dx;
  check<ConfigError>(std::isfinite(wall_height) && wall_height >= s.depth, "tank: the water (depth ", s.depth,
                     ") does not fit the tank (walls ", wall_height, " high)");
  // Before anything is made: a tank of more than 2e7 lattice points (its water, walls and the air
  // between them) is beyond what a run could hold.
  const Real points = std::pow(s.nx + 2.0 * s.wall_layers, s.dim - 1) * (wall_height / dx + s.wall_layers);
  check<ConfigError>(points <= 2e7, "tank: ", points, " lattice points (width ", s.width, ", walls ", wall_height,
                     " high, dx ", dx, ") is over 2e7 particles");
  const int nh = whole_spacings(s.depth, dx, "depth");
  const int nt = whole_spacings(wall_height, dx, "wall height");
  const int nc = s.column_width > 0 ? whole_spacings(s.column_width, dx, "column width") : s.nx;
  const int d = s.dim, v = d - 1;  // v: the vertical axis
  PointCloud c;
  c.dim = d;
  c.spacing = dx;
  c.normals.clear();
  Vec3 hi = Vec3::Zero();
  for (int a = 0; a < v; ++a) hi[a] = s.width;
  // The box reaches a water depth above the walls: room for the surface to move and splash; a
  // particle beyond it has been flung out of the tank (FlowSolver stops there).
  hi[v] = wall_height + s.depth;
  c.domain = Domain::box(d, Vec3::Zero(), hi);
  check<ConfigError>(s.wall_layers >= 1 && s.wall_layers <= 8, "tank: wall layers must be in [1, 8], got ", s.wall_layers);
  const int nk = d == 3 ? s.nx : 0, extra = s.wall_layers - 1, ek = d == 3 ? extra : 0;
  std::vector<Vec3> positions, normals;
  std::vector<Tag> tags;
  for (int i = -extra; i <= s.nx + extra; ++i)
    for (int k = -ek; k <= nk + ek; ++k)
      for (int j = -extra; j <= nt; ++j) {
        // Horizontal indices (i, k) and the vertical j; the faces' extra layers lie outside the box.
        const int idx[2] = {i, k};
        Vec3 x = Vec3::Zero(), n = Vec3::Zero();
        for (int a = 0; a < v; ++a) {
          x[a] = idx[a] * dx;
          if (idx[a] <= 0) n[a] = -1;
          if (idx[a] >= s.nx) n[a] = 1;
        }
        x[v] = j * dx;
        if (j <= 0) n[v] = -1;
        if (n.squaredNorm() > 0) {
          positions.push_back(x);
          normals.push_back(n.normalized());
          tags.push_back(Tag::Dirichlet);
          continue;
        }
        if (j > nh || i > nc) continue;  // above the water, or beside the column
        positions.push_back(x);
        normals.push_back(Vec3::Zero());
        tags.push_back(Tag::Interior);
      }
  c.positions = std::move(positions);
  c.normals = std::move(normals);
  c.tags = std::move(tags);
  if (s.jitter > 0) {
    // The water's top row keeps its height: a flat surface at rest (a rough one is not at rest:
    // gravity flattens it, in waves of speed (g roughness)^½).
    std::vector<Real> height(c.positions.size());
    for (std::size_t i = 0; i < height.size(); ++i) height[i] = c.positions[i][v];
    PerturbOptions p;
    p.delta = s.jitter;
    p.seed = s.seed;
    perturb(c, p);
    for (std::size_t i = 0; i < height.size(); ++i)
      if (c.tags[i] == Tag::Interior && std::abs(height[i] - nh * dx) < 1e-9 * dx) c.positions[i][v] = height[i];
  }
  return c;
}

HydrostaticRow run_hydrostatic(const HydrostaticRunOptions& o) {
  check<ConfigError>(std::isfinite(o.gravity) && o.gravity > 0, "hydrostatic tank: the gravity must be positive, got ",
                     o.gravity, " (without it nothing holds the water in its tank)");
  check<ConfigError>(std::isfinite(o.t_end) && o.t_end > 0, "hydrostatic tank: the end time must be positive, got ",
                     o.t_end);
  check<ConfigError>(std::isfinite(o.ramp) && o.ramp >= 0, "hydrostatic tank: the ramp time must be >= 0, got ", o.ramp);
  check<ConfigError>(std::isfinite(o.dt) && o.dt >= 0, "hydrostatic tank: the time step must be finite and >= 0, got ",
                     o.dt);
  check<ConfigError>(o.tank.column_width == 0 || o.tank.column_width == o.tank.width,
                     "hydrostatic tank: the water fills the tank's width (a column is a dam break)");
  const Stopwatch setup;
  TankSpec spec = o.tank;
  // Walls up to the water's level unless asked otherwise (the documented tables were measured so;
  // higher walls run too since the flow's free-surface condition limit, docs/free_surface.md).
  if (spec.wall_height == 0) spec.wall_height = spec.depth;
  PointCloud cloud = tank_cloud(spec);
  const int d = cloud.dim, v = d - 1;
  const Real H = o.tank.depth, g = o.gravity, dx = cloud.spacing;
  FlowOptions fo = o.flow;
  fo.free_surface = true;
  fo.body_force = Vec3::Zero();
  fo.body_force[v] = -g;
  fo.body_force_ramp = o.ramp;
  HydrostaticRow row;
  row.nx = o.tank.nx;
  row.particles = cloud.size();
  row.water_particles = cloud.count(Tag::Interior);
  const Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(cloud.size(), d);
  FlowSolver solver(std::move(cloud), u0, fo);
  row.seconds_setup = setup.seconds();
  const Real scale = std::sqrt(g * H);
  const Real dt_target = o.dt > 0 ? o.dt : o.t_end;  // the stability limit decides
  detail::check_study_length("hydrostatic tank", o.t_end, o.dt > 0 ? o.dt : solver.stable_time_step(0.9));
  row.dt = std::numeric_limits<Real>::infinity();
  const std::vector<char>& wall = solver.walls().is_wall;
  auto water_extent = [&] {
    for (std::size_t i = 0; i < wall.size(); ++i) {
      if (wall[i]) continue;
      const Real y = solver.positions()[i][v];
      row.surface_rise = std::max(row.surface_rise, (y - H) / dx);
    }
  };
  // The top row's lowest particle: how far the surface sank.
  std::vector<Index> top;
  for (std::size_t i = 0; i < wall.size(); ++i)
    if (!wall[i] && std::abs(solver.positions()[i][v] - H) <= 0.5 * dx) top.push_back(static_cast<Index>(i));
  const Stopwatch watch;
  detail::StepCosts costs;
  while (solver.time() < o.t_end * (1 - 1e-12)) {
    const Real dt = detail::next_study_step(solver, "hydrostatic tank", o.dt, dt_target, o.t_end, costs.steps, row.dt,
                                            "more particles or a smaller time step");
    costs.add(solver.step(dt));
    row.dt = std::min(row.dt, dt);
    Real speed = 0;
    for (std::size_t i = 0; i < wall.size(); ++i)
      if (!wall[i]) speed = std::max(speed, solver.velocity().row(static_cast<Index>(i)).norm());
    if (solver.time() >= o.ramp) row.max_speed_after_ramp = std::max(row.max_speed_after_ramp, speed / scale);
    row.max_speed = speed / scale;
    water_extent();
    for (const Index i : top)
      row.surface_drop = std::max(row.surface_drop, (H - solver.positions()[static_cast<std::size_t>(i)][v]) / dx);
    if (o.on_step) o.on_step(solver);
  }
  costs.write(row, watch.seconds());
  row.t = solver.time();
  row.max_div_u = solver.last().max_div_u;
  row.surface_particles = solver.last().surface_particles;
  // The pressure at the end, sampled along the vertical centre line (the bottom's centre first).
  const Field p = solver.pressure();
  std::vector<Vec3> line;
  for (int k = 0; k <= 40; ++k) {
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < v; ++a) x[a] = 0.5 * o.tank.width;
    x[v] = H * k / 40.0;
    line.push_back(x);
  }
  const Eigen::MatrixXd sampled = sample_field(solver.operators().cloud(), Eigen::MatrixXd(p), line, 2.5 * dx);
  // Against the gravity in force at the end, whose weight the pressure carries: before the ramp
  // ends that is a fraction of g (the errors stay relative to the full weight g H).
  const Real g_end = solver.body_force(solver.time()).norm();
  for (std::size_t k = 0; k < line.size(); ++k) {
    const Real y = line[k][v], exact = g_end * (H - y);
    row.line_y.push_back(y);
    row.line_p.push_back(sampled(static_cast<Index>(k), 0));
    row.line_exact.push_back(exact);
    row.pressure_profile_error = std::max(row.pressure_profile_error, std::abs(row.line_p.back() - exact) / (g * H));
  }
  row.bottom_pressure = row.line_p.front();
  row.bottom_pressure_error = std::abs(row.bottom_pressure - g_end * H) / (g * H);
  return row;
}

}  // namespace vrsph
