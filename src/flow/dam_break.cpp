// SPDX-License-Identifier: BSD-3-Clause
// The dam break against Martin & Moyce (1952) and Koshizuka & Oka (1996) (dam_break.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/tank.hpp>
#include <vrsph/kernels/kernel.hpp>
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

DamBreakGeometry parse_dam_break_geometry(const std::string& name) {
  if (name == "martin-moyce") return DamBreakGeometry::MartinMoyce;
  if (name == "buchner") return DamBreakGeometry::Buchner;
  throw ConfigError(detail::concat("unknown dam-break geometry '", name, "' (martin-moyce | buchner)"));
}

std::string to_string(DamBreakGeometry g) { return g == DamBreakGeometry::Buchner ? "buchner" : "martin-moyce"; }

const SurgeCurve& buchner_probe_reference() {
  // (T = t (g/H)^½, p/(ρgH)) at P1, read off Buchner (2002) as digitised in TrixiParticles.jl's
  // validation (exp_pressure_sensor_P1.csv).
  static const SurgeCurve curve = {
      "buchner P1",
      {2.02512, 2.06281, 2.12405, 2.16801, 2.24966, 2.27165, 2.42553, 2.47263, 2.49148, 2.55271, 2.61552, 2.62337,
       2.65007, 2.67205, 2.68932, 2.77411, 2.83535, 2.90287, 2.96097, 3.02221, 3.02535, 3.13212, 3.19336, 3.23105,
       3.36765, 3.51996, 3.67856, 3.90467, 4.06012, 4.22342, 4.35532, 4.45267, 4.57044, 4.71961, 4.81696, 4.91745,
       5.03836, 5.15926, 5.30372, 5.34141, 5.44504, 5.53454, 5.58636, 5.61463, 5.69157, 5.74966, 5.78107, 5.78735,
       5.80619, 5.81404, 5.81561, 5.82503, 5.83288, 5.83603, 5.869, 5.88156, 5.90354, 5.92082, 5.93652, 5.96792,
       6.04172, 6.05114, 6.10296, 6.15007, 6.2223, 6.28039, 6.31494, 6.31965, 6.36048, 6.3699, 6.38874, 6.41072,
       6.42328, 6.5175, 6.56146, 6.6227, 6.6541, 6.70749, 6.74204, 6.75774, 6.77187, 6.79385, 6.8127, 6.88022,
       6.88807, 6.91162, 6.93517, 7.00112, 7.02467, 7.06079, 7.10947, 7.12674, 7.14715, 7.15814, 7.18327, 7.23194,
       7.25707, 7.29946},
      {-0.01792, 0.02087, -0.02169, 0.01112, -0.02026, 0.01033, -0.01511, 0.07666, 0.15352, 0.26544, 0.37138,
       0.46317, 0.56241, 0.60494, 0.66239, 0.68698, 0.67203, 0.66081, 0.64586, 0.64285, 0.60106, 0.57862, 0.56367,
       0.54574, 0.54121, 0.54487, 0.54108, 0.54396, 0.55584, 0.55801, 0.55497, 0.55119, 0.54293, 0.53765, 0.51746,
       0.51293, 0.51438, 0.51358, 0.5262, 0.54335, 0.54928, 0.56939, 0.58802, 0.60741, 0.6335, 0.65586, 0.67451,
       0.69092, 0.71554, 0.83196, 0.7424, 0.76479, 0.87672, 0.85956, 0.83939, 0.7976, 0.76475, 0.72445, 0.67892,
       0.64756, 0.60947, 0.57887, 0.55721, 0.54301, 0.55641, 0.58101, 0.60562, 0.61831, 0.56232, 0.59441, 0.54589,
       0.51901, 0.49662, 0.48539, 0.4682, 0.49206, 0.50249, 0.52187, 0.53902, 0.47633, 0.54797, 0.51139, 0.47257,
       0.41732, 0.45762, 0.43223, 0.40461, 0.43817, 0.44786, 0.46799, 0.4926, 0.50453, 0.45228, 0.47616, 0.43958,
       0.43732, 0.41641, 0.41565}};
  return curve;
}

namespace {

// The first peak (T <= 3.5) and the plateau's mean (3 <= T <= 5) of the probe and of Buchner's
// record at the same sample times; NaN where the run has no sample there.
void summarise_probe(DamBreakRun& run) {
  const SurgeCurve& ref = buchner_probe_reference();
  Real sum = 0, ref_sum = 0;
  int count = 0;
  for (const DamBreakSample& s : run.samples) {
    if (s.t_star <= 3.5 && (!(s.probe_pressure <= run.probe_peak))) {
      run.probe_peak = s.probe_pressure;
      run.probe_peak_t_star = s.t_star;
    }
    if (s.t_star >= 3 && s.t_star <= 5) {
      sum += s.probe_pressure;
      ref_sum += s.probe_reference;
      ++count;
    }
  }
  if (run.samples.empty() || run.samples.back().t_star < 3.5) run.probe_peak = run.probe_peak_t_star = std::numeric_limits<Real>::quiet_NaN();
  if (count > 0 && run.samples.back().t_star >= 5 * (1 - 1e-9)) {
    run.probe_plateau = sum / count;
    run.reference_plateau = ref_sum / count;
  }
  for (std::size_t k = 0; k < ref.t_star.size() && ref.t_star[k] <= 3.5; ++k)
    if (!(ref.z_over_l[k] <= run.reference_peak)) {
      run.reference_peak = ref.z_over_l[k];
      run.reference_peak_t_star = ref.t_star[k];
    }
}

}  // namespace

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

const SurgeCurve& martin_moyce_height_reference() {
  // Martin & Moyce (1952) Table 6, n² = 2: (τ, H) with τ = t (g/a)^½, H = η / (n² a). With a = L:
  // T = t (2g/L)^½ = √2 τ and η/L = 2H.
  static const SurgeCurve curve = [] {
    const std::vector<Real> tau = {0.56, 0.77, 0.93, 1.08, 1.28, 1.46, 1.66, 1.84, 2.00,
                                   2.21, 2.45, 2.70, 3.06, 3.44, 4.20, 5.25, 7.40};
    const std::vector<Real> height = {0.94, 0.89, 0.83, 0.78, 0.72, 0.67, 0.61, 0.56, 0.50,
                                      0.44, 0.39, 0.33, 0.28, 0.22, 0.17, 0.11, 0.06};
    SurgeCurve c;
    c.name = "martin-moyce height";
    for (std::size_t k = 0; k < tau.size(); ++k) {
      c.t_star.push_back(std::sqrt(2.0) * tau[k]);
      c.z_over_l.push_back(2 * height[k]);
    }
    return c;
  }();
  return curve;
}

DamBreakRun run_dam_break(const DamBreakRunOptions& o) {
  check<ConfigError>(o.flow.frame == FlowFrame::Lagrangian, "dam break: the water moves: the frame must be lagrangian");
  check<ConfigError>(std::isfinite(o.t_star_end) && o.t_star_end > 0, "dam break: the end time must be positive, got ",
                     o.t_star_end);
  check<ConfigError>(std::isfinite(o.cfl) && o.cfl > 0 && o.cfl <= 1, "dam break: the CFL number must be in (0, 1], got ",
                     o.cfl);
  check<ConfigError>(std::isfinite(o.sample) && o.sample > 0, "dam break: the sampling interval must be positive, got ",
                     o.sample);
  check<ConfigError>(std::isfinite(o.wall_gap) && o.wall_gap < 1, "dam break: the wall gap must be below 1 particle "
                     "spacing, got ", o.wall_gap);
  const bool buchner = o.geometry == DamBreakGeometry::Buchner;
  // Martin–Moyce: L = 1, g = 1, T = t √2; the tank 4L wide, its walls 3L high. Buchner: H = 1,
  // T = t; the column 2H wide, the tank 5.366 H (to the nearest spacing), the walls 6H high.
  constexpr Real L = 1, g = 1;
  const int tank_intervals = buchner ? static_cast<int>(std::lround(5.366 * o.nx)) : 4 * o.nx;
  const Real width = buchner ? static_cast<Real>(tank_intervals) / o.nx : 4;
  const Real time_scale = buchner ? std::sqrt(g / L) : std::sqrt(2 * g / L);
  TankSpec tank;
  tank.nx = tank_intervals;
  tank.width = width;
  tank.depth = buchner ? L : 2 * L;
  tank.column_width = buchner ? 2 * L : L;
  tank.wall_height = buchner ? 6 * L : 3 * L;  // Buchner: the run-up on the far wall reached 5H at nx = 10
  tank.wall_layers = o.wall_layers;
  tank.jitter = o.jitter;
  tank.seed = o.seed;
  const Stopwatch setup;
  PointCloud cloud = tank_cloud(tank);
  const Real dx = cloud.spacing;
  FlowOptions fo = o.flow;
  if (fo.wall_gap == 0) fo.wall_gap = std::max<Real>(o.wall_gap, 0);
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
  // Buchner's P1: the water's pressure near the far wall's face at the probe's height, each
  // particle weighted by the kernel of the flow's support (Shepard); 0 where no water reaches.
  // Not sample_field's quadratic fit (analysis/point_sampling.hpp): at the wall's face the water
  // lies on one side only, where a fit extrapolates, and it needs six particles that the thin
  // sheet at the wall often does not have (it would throw).
  const Vec3 probe(width, buchner_probe_height * L, 0);
  auto probe_pressure = [&] {
    const Field p = solver.pressure();
    const Kernel kernel(fo.operators.kernel, 2, solver.operators().radius());
    Real weight = 0, sum = 0;
    for (std::size_t i = 0; i < wall.size(); ++i) {
      if (wall[i]) continue;
      const Real w = kernel.W((solver.positions()[i] - probe).norm());
      weight += w;
      sum += w * p[static_cast<Index>(i)];
    }
    return weight > 0 ? sum / weight / (g * L) : 0.0;
  };
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
    if (buchner) {  // the fronts' references are for the other tank: they stay NaN
      s.experiment_low = s.experiment_high = s.outside_experiments = s.mps = std::numeric_limits<Real>::quiet_NaN();
      s.probe_pressure = probe_pressure();
      s.probe_reference = buchner_probe_reference().at(s.t_star);
    } else {
      const Real a = refs[0].at(s.t_star), b = refs[1].at(s.t_star);
      s.experiment_low = std::min(a, b);
      s.experiment_high = std::max(a, b);
      if (std::isfinite(a) && std::isfinite(b))
        s.outside_experiments = std::max({0.0, s.experiment_low - s.front_z_over_l, s.front_z_over_l - s.experiment_high});
      else
        s.outside_experiments = std::numeric_limits<Real>::quiet_NaN();
      s.mps = refs[2].at(s.t_star);
      s.experiment_height = martin_moyce_height_reference().at(s.t_star);
    }
    s.max_speed = speed / std::sqrt(g * L);
    s.surface_particles = solver.last().surface_particles;
    s.min_spacing = solver.last().min_spacing;
    return s;
  };
  run.samples.push_back(sample());
  // A run that would take over 1e7 steps at the step at rest (the moving water's are shorter) is
  // refused before it starts, not after 1e7 steps: since the run goes on past the far wall, an end
  // time of 1e300 would otherwise run for ever.
  const Real t_end = o.t_star_end / time_scale;
  const Real dt_at_rest = std::min(0.9 * solver.stable_time_step(), o.cfl * dx / std::sqrt(g * dx));
  detail::check_study_length("dam break", t_end, dt_at_rest);
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
    if (s.t_star >= next * (1 - 1e-9) || (far && !run.reached_far_wall) || solver.time() >= t_end * (1 - 1e-12)) {
      run.samples.push_back(s);
      while (next <= s.t_star * (1 + 1e-9)) next += o.sample;
    }
    if (far && !run.reached_far_wall) {
      run.reached_far_wall = true;
      run.far_wall_t_star = s.t_star;
    }
  }
  costs.write(run, watch.seconds());
  run.t_star = solver.time() * time_scale;
  for (const DamBreakSample& s : run.samples)
    if (s.front_z_over_l <= 3.5 && std::isfinite(s.outside_experiments))
      run.max_outside_experiments = std::max(run.max_outside_experiments, s.outside_experiments);
  for (const DamBreakSample& s : run.samples) {
    if (run.reached_far_wall && s.t_star >= run.far_wall_t_star) break;
    if (!std::isfinite(s.experiment_height)) continue;
    const Real d = std::abs(s.column_height_over_l - s.experiment_height);
    run.max_height_deviation = std::isfinite(run.max_height_deviation) ? std::max(run.max_height_deviation, d) : d;
  }
  if (buchner) {
    run.max_outside_experiments = std::numeric_limits<Real>::quiet_NaN();
    summarise_probe(run);
  }
  return run;
}

}  // namespace vrsph
