// SPDX-License-Identifier: BSD-3-Clause
// The lid-driven cavity against Ghia, Ghia & Shin (1982) (cavity.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
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
// The Lagrangian cavity's centre-line samples, taken every probe interval: a single one
// fluctuates with the particles' arrangement, so the steady test compares the means of the last
// two windows of them, and the profiles reported are the last window's mean.
class ProbeWindows {
 public:
  explicit ProbeWindows(std::size_t window) : window_(window) {}
  void add(Real t, std::vector<Real> sample) {
    times_.push_back(t);
    samples_.push_back(std::move(sample));
  }
  Real last_time() const { return times_.empty() ? 0 : times_.back(); }
  bool has_rate() const { return samples_.size() >= 2 * window_; }
  bool has_mean() const { return samples_.size() >= window_; }
  /// The largest change of the first `count` values between the last two windows' means, over
  /// the time between them (has_rate()).
  Real rate(std::size_t count) const {
    const std::size_t n = samples_.size();
    const std::vector<Real> a = mean(n - window_), b = mean(n);
    Real change = 0;
    for (std::size_t j = 0; j < count; ++j) change = std::max(change, std::abs(b[j] - a[j]));
    return change / (times_[n - 1] - times_[n - 1 - window_]);
  }
  /// Whether the last two windows' means of each of the first `count` values differ by less than
  /// twice the standard error of that difference (has_rate()): steady within the fluctuations.
  bool within_noise(std::size_t count) const {
    const std::size_t n = samples_.size();
    const std::vector<Real> a = mean(n - window_), b = mean(n);
    const std::vector<Real> va = variance(n - window_, a), vb = variance(n, b);
    for (std::size_t j = 0; j < count; ++j)
      if (std::abs(b[j] - a[j]) > 2 * std::sqrt((va[j] + vb[j]) / static_cast<Real>(window_))) return false;
    return true;
  }
  /// The last window's mean (has_mean()), the time it spans, and the largest standard deviation
  /// of the first `count` values about it.
  std::vector<Real> mean() const { return mean(samples_.size()); }
  Real span() const { return times_.back() - times_[times_.size() - window_]; }
  Real fluctuation(std::size_t count) const {
    const std::vector<Real> v = variance(samples_.size(), mean());
    Real worst = 0;
    for (std::size_t j = 0; j < count; ++j) worst = std::max(worst, std::sqrt(v[j]));
    return worst;
  }

 private:
  std::vector<Real> variance(std::size_t end, const std::vector<Real>& m) const {  // of that window about m
    std::vector<Real> v(m.size(), 0.0);
    for (std::size_t k = end - window_; k < end; ++k)
      for (std::size_t j = 0; j < m.size(); ++j)
        v[j] += (samples_[k][j] - m[j]) * (samples_[k][j] - m[j]) / static_cast<Real>(window_);
    return v;
  }
  std::vector<Real> mean(std::size_t end) const {  // of the window that ends before sample `end`
    std::vector<Real> m(samples_.front().size(), 0.0);
    for (std::size_t k = end - window_; k < end; ++k)
      for (std::size_t j = 0; j < m.size(); ++j) m[j] += samples_[k][j] / static_cast<Real>(window_);
    return m;
  }
  std::size_t window_;
  std::vector<Real> times_;
  std::vector<std::vector<Real>> samples_;
};
}  // namespace

PointCloud cavity_cloud(const CavityCloudSpec& spec) {
  check<ConfigError>(spec.nx >= 8 && spec.nx <= 4096, "cavity cloud: nx (intervals per side) must be in [8, 4096], got ",
                     spec.nx);
  check<ConfigError>(std::isfinite(spec.jitter) && spec.jitter >= 0 && spec.jitter < 0.5,
                     "cavity cloud: the jitter must be in [0, 0.5) particle spacings, got ", spec.jitter);
  check<ConfigError>(spec.wall_layers >= 0 && spec.wall_layers <= 8, "cavity cloud: wall layers must be in [1, 8] (0: "
                     "one), got ", spec.wall_layers);
  PointCloud cloud = vertex_lattice(Domain::unit_box(2), spec.nx);
  // The extra layers lie outside the square, after the lattice's particles (whose numbers, and
  // so their jitter, stay those of one layer).
  const int extra = std::max(spec.wall_layers, 1) - 1, n = spec.nx;
  for (int i = -extra; i <= n + extra; ++i)
    for (int j = -extra; j <= n + extra; ++j) {
      if (i >= 0 && i <= n && j >= 0 && j <= n) continue;
      const Vec3 normal(i < 0 ? -1 : i > n ? 1 : 0, j < 0 ? -1 : j > n ? 1 : 0, 0);
      cloud.positions.emplace_back(static_cast<Real>(i) / n, static_cast<Real>(j) / n, 0);
      cloud.normals.push_back(normal.normalized());
      cloud.tags.push_back(Tag::Dirichlet);
    }
  if (spec.jitter > 0) {
    PerturbOptions p;
    p.delta = spec.jitter;
    p.seed = spec.seed;
    perturb(cloud, p);
  }
  return cloud;
}

Vec3 cavity_lid_velocity(const Vec3& x) {
  constexpr Real tol = 1e-12;  // the lid's outer layers lie above it, between the corners too
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
  check<ConfigError>(std::isfinite(o.lagrangian_probe_interval) && o.lagrangian_probe_interval > 0,
                     "cavity: the lagrangian probe interval must be positive, got ", o.lagrangian_probe_interval);
  check<ConfigError>(std::isfinite(o.lagrangian_wall_gap) && o.lagrangian_wall_gap < 1,
                     "cavity: the lagrangian wall gap must be below 1 particle spacing, got ", o.lagrangian_wall_gap);
  check<ConfigError>(o.lagrangian_window >= 1 && o.lagrangian_window <= 1000,
                     "cavity: the lagrangian window must be in [1, 1000] probes, got ", o.lagrangian_window);
  const bool lagrangian = o.flow.frame == FlowFrame::Lagrangian;
  const Stopwatch setup;
  CavityCloudSpec spec = o.cloud;
  if (spec.wall_layers == 0) spec.wall_layers = lagrangian ? 3 : 1;
  PointCloud cloud = cavity_cloud(spec);
  FlowOptions fo = o.flow;
  fo.nu = 1 / o.re;
  if (lagrangian && fo.wall_gap == 0) fo.wall_gap = std::max<Real>(o.lagrangian_wall_gap, 0);
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
  // Profiles from a quadratic moving least-squares fit over 2.5 dx: its error is far below the
  // deviations measured (docs/flow.md).
  const Real radius = 2.5 * dx;
  for (int k = 0; k <= 100; ++k) row.line.push_back(k / 100.0);
  const std::size_t gu = ghia.y.size(), gv = ghia.x.size(), nl = row.line.size();
  // All four profiles in one vector: u at Ghia's heights, v at Ghia's abscissae, then u and v on the line.
  auto sample = [&] {
    std::vector<Real> u, v, ul, vl;
    centre_lines(solver, radius, ghia.y, ghia.x, u, v);
    centre_lines(solver, radius, row.line, row.line, ul, vl);
    for (auto* part : {&v, &ul, &vl}) u.insert(u.end(), part->begin(), part->end());
    return u;
  };
  ProbeWindows probes(static_cast<std::size_t>(o.lagrangian_window));
  while (solver.time() < o.t_end * (1 - 1e-12)) {
    const Real dt = detail::next_study_step(solver, "cavity", o.dt, dt_target, o.t_end, costs.steps, row.dt,
                                            "more particles, a hyperviscosity or a smaller --cfl");
    const Eigen::MatrixXd before = solver.velocity();
    costs.add(solver.step(dt));
    row.dt = std::min(row.dt, dt);
    row.wall_pushes += solver.last().wall_pushes;
    bool tested = false, steady_in_noise = false;
    if (!lagrangian) {
      Real change = 0;
      for (Index i = 0; i < before.rows(); ++i)
        if (!wall[static_cast<std::size_t>(i)]) change = std::max(change, (solver.velocity().row(i) - before.row(i)).norm());
      row.steady_residual = change / dt;
      tested = true;
    } else if (solver.time() >= probes.last_time() + o.lagrangian_probe_interval * (1 - 1e-9)) {
      probes.add(solver.time(), sample());
      if (probes.has_rate()) {
        row.steady_residual = probes.rate(gu + gv);
        tested = true;
        steady_in_noise = probes.within_noise(gu + gv);
      }
    }
    if (o.on_step) o.on_step(solver, row.steady_residual);
    if (tested && (row.steady_residual < o.steady_tolerance || steady_in_noise)) {
      row.steady = true;
      break;
    }
  }
  costs.write(row, watch.seconds());
  row.t = solver.time();
  row.max_div_u = solver.last().max_div_u;
  row.kinetic_energy = solver.last().kinetic_energy;
  // Lagrangian runs too short for two windows have not been tested: no rate to report.
  if (lagrangian && !probes.has_rate()) row.steady_residual = std::numeric_limits<Real>::quiet_NaN();
  std::vector<Real> profile = sample();
  if (lagrangian && probes.has_mean()) {
    profile = probes.mean();
    row.average_time = probes.span();
    row.profile_fluctuation = probes.fluctuation(gu + gv);
  }
  const auto part = [&profile](std::size_t from, std::size_t count) {
    return std::vector<Real>(profile.begin() + static_cast<std::ptrdiff_t>(from),
                             profile.begin() + static_cast<std::ptrdiff_t>(from + count));
  };
  row.u_at_ghia = part(0, gu);
  row.v_at_ghia = part(gu, gv);
  row.u_line = part(gu + gv, nl);
  row.v_line = part(gu + gv + nl, nl);
  row.ghia_max_deviation_u = max_deviation(ghia.y, row.u_at_ghia, ghia.u);
  row.ghia_max_deviation_v = max_deviation(ghia.x, row.v_at_ghia, ghia.v);
  row.reference_max_deviation_u = max_deviation(ghia.y, row.u_at_ghia, ghia.u_converged);
  row.reference_max_deviation_v = max_deviation(ghia.x, row.v_at_ghia, ghia.v_converged);
  return row;
}

}  // namespace vrsph
