// SPDX-License-Identifier: BSD-3-Clause
// The dam break against Martin & Moyce (1952) and Koshizuka & Oka (1996) (dam_break.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/tank.hpp>
#include "study_step.hpp"

namespace vrsph {

Real SurgeCurve::at(Real t) const {
  if (t_star.empty() || t < t_star.front() || t > t_star.back()) return std::numeric_limits<Real>::quiet_NaN();
  const auto hi = std::upper_bound(t_star.begin(), t_star.end(), t);
  if (hi == t_star.end()) return z_over_l.back();
  const auto k = static_cast<std::size_t>(hi - t_star.begin());
  const Real s = (t - t_star[k - 1]) / (t_star[k] - t_star[k - 1]);
  return z_over_l[k - 1] + s * (z_over_l[k] - z_over_l[k - 1]);
}

const std::vector<SurgeCurve>& dam_break_references() {
  // (T, z/L) read off Fig. 3 of Martin & Moyce (1952) for n² = 2, and off Koshizuka & Oka's
  // (1996) MPS curve; the points as digitised in PySPH's examples (db_exp_data.py).
  static const std::vector<SurgeCurve> curves = {
      {"martin-moyce a=1.125in",
       {0.849, 1.212, 1.602, 2.283, 2.950, 3.598, 3.905, 4.592, 4.961, 5.316},
       {1.245, 1.443, 1.884, 2.689, 3.728, 4.528, 4.999, 5.841, 6.271, 6.717}},
      {"martin-moyce a=2.25in",
       {0.832, 1.219, 1.997, 2.547, 3.345, 4.034, 4.418, 5.091, 5.685, 6.306, 6.822, 7.439, 8.031, 8.633, 9.237},
       {1.217, 1.474, 2.292, 2.995, 4.134, 4.944, 5.881, 6.980, 7.945, 8.966, 9.986, 10.963, 11.977, 13.005, 13.970}},
      {"koshizuka-oka mps",
       {0.0, 0.381, 0.769, 1.153, 1.537, 1.935, 2.323, 2.719, 3.096},
       {1.000, 1.111, 1.252, 1.505, 1.892, 2.241, 2.615, 3.003, 3.624}},
  };
  return curves;
}

DamBreakRun run_dam_break(const DamBreakRunOptions& o) {
  check<ConfigError>(o.flow.frame == FlowFrame::Lagrangian, "dam break: the water moves: the frame must be lagrangian");
  check<ConfigError>(std::isfinite(o.t_star_end) && o.t_star_end > 0, "dam break: the end time must be positive, got ",
                     o.t_star_end);
  check<ConfigError>(std::isfinite(o.cfl) && o.cfl > 0 && o.cfl <= 1, "dam break: the CFL number must be in (0, 1], got ",
                     o.cfl);
  check<ConfigError>(std::isfinite(o.sample) && o.sample > 0, "dam break: the sampling interval must be positive, got ",
                     o.sample);
  // L = 1, g = 1: T = t √2. The tank is 4L wide, its walls 3L high.
  constexpr Real L = 1, g = 1, width = 4;
  const Real time_scale = std::sqrt(2 * g / L);
  TankSpec tank;
  tank.nx = static_cast<int>(width / L) * o.nx;
  tank.width = width;
  tank.depth = 2 * L;
  tank.column_width = L;
  tank.wall_height = 3 * L;
  tank.wall_layers = o.wall_layers;
  tank.jitter = o.jitter;
  tank.seed = o.seed;
  const Stopwatch setup;
  PointCloud cloud = tank_cloud(tank);
  const Real dx = cloud.spacing;
  FlowOptions fo = o.flow;
  fo.free_surface = true;
  fo.body_force = Vec3(0, -g, 0);
  DamBreakRun run;
  run.nx = o.nx;
  run.particles = cloud.size();
  run.water_particles = cloud.count(Tag::Interior);
  const Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(cloud.size(), 2);
  FlowSolver solver(std::move(cloud), u0, fo);
  run.seconds_setup = setup.seconds();
  const std::vector<char>& wall = solver.walls().is_wall;
  const std::vector<SurgeCurve>& refs = dam_break_references();
  auto sample = [&] {
    DamBreakSample s;
    s.t_star = solver.time() * time_scale;
    Real front = 0, column = 0, speed = 0;
    for (std::size_t i = 0; i < wall.size(); ++i) {
      if (wall[i]) continue;
      const Vec3& x = solver.positions()[i];
      front = std::max(front, x[0]);
      if (x[0] < 2 * dx) column = std::max(column, x[1]);
      speed = std::max(speed, solver.velocity().row(static_cast<Index>(i)).norm());
    }
    s.front_z_over_l = front / L;
    s.column_height_over_l = column / L;
    const Real a = refs[0].at(s.t_star), b = refs[1].at(s.t_star);
    s.experiment_low = std::min(a, b);
    s.experiment_high = std::max(a, b);
    if (std::isfinite(a) && std::isfinite(b))
      s.outside_experiments = std::max({0.0, s.experiment_low - s.front_z_over_l, s.front_z_over_l - s.experiment_high});
    else
      s.outside_experiments = std::numeric_limits<Real>::quiet_NaN();
    s.mps = refs[2].at(s.t_star);
    s.max_speed = speed / std::sqrt(g * L);
    s.surface_particles = solver.last().surface_particles;
    s.min_spacing = solver.last().min_spacing;
    return s;
  };
  run.samples.push_back(sample());
  // A step that would never get the front to the far wall (at T ≈ 3.3 in every run measured; 5
  // with room) is refused before the run, not after 1e7 steps.
  const Real t_end = o.t_star_end / time_scale;
  const Real dt_at_rest = std::min(0.9 * solver.stable_time_step(), o.cfl * dx / std::sqrt(g * dx));
  detail::check_study_length("dam break", std::min(t_end, 5 / time_scale), dt_at_rest);
  const Stopwatch watch;
  detail::StepCosts costs;
  Real next = o.sample;
  while (solver.time() < t_end * (1 - 1e-12)) {
    check<NumericalError>(costs.steps < 10'000'000, "dam break: 1e7 steps reached at T = ", solver.time() * time_scale);
    const Real speed = std::max(solver.last().max_speed, std::sqrt(g * dx));
    Real dt = std::min(0.9 * solver.stable_time_step(), o.cfl * dx / speed);
    // Against the step at rest, not the CFL target, which shrinks with the speed it bounds.
    if (detail::step_collapsed(solver, costs.steps, dt, dt_at_rest, "a smaller --cfl, more particles", run.stopped)) break;
    dt = std::min(dt, t_end - solver.time());
    try {
      costs.add(solver.step(dt));
    } catch (const NumericalError& e) {
      run.stopped = e.what();
      break;
    } catch (const GeometryError& e) {
      run.stopped = e.what();
      break;
    }
    if (o.on_step) o.on_step(solver);
    const DamBreakSample s = sample();
    const bool far = s.front_z_over_l >= width / L - 1.5 * dx / L;
    if (s.t_star >= next * (1 - 1e-9) || far || solver.time() >= t_end * (1 - 1e-12)) {
      run.samples.push_back(s);
      while (next <= s.t_star * (1 + 1e-9)) next += o.sample;
    }
    if (far) {
      run.reached_far_wall = true;
      break;
    }
  }
  costs.write(run, watch.seconds());
  run.t_star = solver.time() * time_scale;
  for (const DamBreakSample& s : run.samples)
    if (s.front_z_over_l <= 3.5 && std::isfinite(s.outside_experiments))
      run.max_outside_experiments = std::max(run.max_outside_experiments, s.outside_experiments);
  return run;
}

}  // namespace vrsph
