// SPDX-License-Identifier: BSD-3-Clause
// The flow layer's convergence studies (flow_study.hpp).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/flow_study.hpp>
#include <vrsph/flow/projection.hpp>
#include "study_step.hpp"

namespace vrsph {

namespace {
constexpr Real two_pi = 2 * std::numbers::pi;

// The potential of the frozen-cloud test and its gradient.
Real potential(const Vec3& x, int dim) {
  const Real z = dim == 3 ? std::cos(two_pi * x[2]) : 1.0;
  return std::sin(two_pi * x[0]) * std::cos(2 * two_pi * x[1]) * z / two_pi;
}
Vec3 potential_gradient(const Vec3& x, int dim) {
  const Real sx = std::sin(two_pi * x[0]), cx = std::cos(two_pi * x[0]);
  const Real sy = std::sin(2 * two_pi * x[1]), cy = std::cos(2 * two_pi * x[1]);
  const Real sz = dim == 3 ? std::sin(two_pi * x[2]) : 0.0, cz = dim == 3 ? std::cos(two_pi * x[2]) : 1.0;
  return {cx * cy * cz, -2 * sx * sy * cz, dim == 3 ? -sx * cy * sz : 0.0};
}

Eigen::MatrixXd sample(const std::vector<Vec3>& x, int dim, const std::function<Vec3(const Vec3&)>& f) {
  Eigen::MatrixXd u(static_cast<Index>(x.size()), dim);
  for (std::size_t i = 0; i < x.size(); ++i) u.row(static_cast<Index>(i)) = f(x[i]).head(dim).transpose();
  return u;
}

Field without_mean(Field v) {
  v.array() -= v.mean();
  return v;
}
}  // namespace

PointCloud periodic_flow_cloud(const FlowCloudSpec& spec) {
  check<ConfigError>(spec.dim == 2 || spec.dim == 3, "flow cloud: the dimension must be 2 or 3, got ", spec.dim);
  check<ConfigError>(spec.nx >= 4 && spec.nx <= 4096, "flow cloud: nx (particles per period) must be in [4, 4096], got ", spec.nx);
  check<ConfigError>(std::isfinite(spec.jitter) && spec.jitter >= 0 && spec.jitter < 0.5,
                     "flow cloud: the jitter must be in [0, 0.5) particle spacings, got ", spec.jitter);
  CloudSpec c;
  c.family = spec.jitter > 0 ? CloudFamily::Perturbed : CloudFamily::Uniform;
  c.box = Domain::unit_box(spec.dim);
  c.box.set_periodic("all");
  c.n = spec.nx;
  c.delta = spec.jitter;
  c.seed = spec.seed;
  return make_study_cloud(c).cloud;
}

ProjectionStudyRow frozen_projection(const FlowCloudSpec& spec, const OperatorsOptions& operators, const SolverOptions& solver) {
  const Stopwatch watch;
  PointCloud cloud = periodic_flow_cloud(spec);
  const int d = cloud.dim;
  const PeriodicVortex vortex{d};
  const std::vector<Vec3> x = cloud.positions;
  const Eigen::MatrixXd exact = sample(x, d, [&](const Vec3& p) { return vortex.velocity(p, 0); });
  const Eigen::MatrixXd grad_phi = sample(x, d, [&](const Vec3& p) { return potential_gradient(p, d); });
  Field phi(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) phi[i] = potential(x[static_cast<std::size_t>(i)], d);
  OperatorsOptions o = operators;
  o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient};
  o.use = StencilUse::Values;
  const Operators ops(std::move(cloud), o);
  SolverOptions so = solver;
  so.dimension = d;
  const PressurePoisson ppe(laplacian_matrix(ops), so);
  const Eigen::MatrixXd ustar = exact + grad_phi;
  const Projected p = project(ops, ppe, ustar);
  ProjectionStudyRow row;
  row.nx = spec.nx;
  row.particles = ops.cloud().size();
  const Eigen::MatrixXd e = p.u - exact;
  row.error_u_inf = e.rowwise().norm().maxCoeff() / vortex.max_speed(0);
  row.error_u_l2 = e.norm() / exact.norm();
  row.error_gradp_inf = e.rowwise().norm().maxCoeff() / grad_phi.rowwise().norm().maxCoeff();
  const Field phi0 = without_mean(phi);
  row.error_phi_inf = (without_mean(p.phi) - phi0).cwiseAbs().maxCoeff() / phi0.cwiseAbs().maxCoeff();
  row.max_div_before = ops.apply(VectorOperator::Divergence, ustar).col(0).cwiseAbs().maxCoeff();
  row.max_div_after = ops.apply(VectorOperator::Divergence, p.u).col(0).cwiseAbs().maxCoeff();
  row.shift = p.shift;
  row.iterations = p.report.iterations;
  row.seconds = watch.seconds();
  return row;
}

VortexErrors vortex_errors(const PeriodicVortex& vortex, const std::vector<Vec3>& x, const Eigen::MatrixXd& u,
                           const Field& p, Real t) {
  const auto n = static_cast<Index>(x.size());
  check<InputError>(u.rows() == n && p.size() == n, "vortex errors: fields of ", u.rows(), " and ", p.size(),
                    " values for ", n, " particles");
  Field pe(n);
  Real diff_sum = 0, speed_sum = 0, diff_max = 0, speed_max = 0;
  for (Index i = 0; i < n; ++i) {
    const Vec3& xi = x[static_cast<std::size_t>(i)];
    const Eigen::VectorXd ue = vortex.velocity(xi, t).head(u.cols());
    const Real diff = (u.row(i).transpose() - ue).norm();
    diff_sum += diff;
    speed_sum += ue.norm();
    diff_max = std::max(diff_max, diff);
    speed_max = std::max(speed_max, u.row(i).norm());
    pe[i] = vortex.pressure(xi, t);
  }
  const Field dp = without_mean(p) - without_mean(pe);
  VortexErrors e;
  e.error_u_mean = diff_sum / speed_sum;
  e.error_u_inf = diff_max / vortex.max_speed(t);
  e.error_p_mean = dp.cwiseAbs().mean() / vortex.max_pressure(t);
  e.error_p_inf = dp.cwiseAbs().maxCoeff() / vortex.max_pressure(t);
  e.decay_rate_error = std::abs(speed_max - vortex.max_speed(t)) / vortex.max_speed(t);
  return e;
}

VortexRunRow run_periodic_vortex(const VortexRunOptions& o) {
  check<ConfigError>(std::isfinite(o.t_end) && o.t_end > 0, "flow: the end time must be positive, got ", o.t_end);
  check<ConfigError>(std::isfinite(o.cfl) && o.cfl > 0 && o.cfl <= 2, "flow: the CFL number must be in (0, 2], got ", o.cfl);
  PointCloud cloud = periodic_flow_cloud(o.cloud);
  PeriodicVortex vortex = o.vortex;
  vortex.dim = cloud.dim;
  check<ConfigError>(std::isfinite(vortex.Re) && vortex.Re > 0 && std::isfinite(vortex.U) && vortex.U > 0,
                     "flow: the Reynolds number and the velocity scale must be positive");
  FlowOptions fo = o.flow;
  fo.nu = vortex.nu();
  const Eigen::MatrixXd u0 = sample(cloud.positions, cloud.dim, [&](const Vec3& p) { return vortex.velocity(p, 0); });
  FlowSolver solver(std::move(cloud), u0, fo);
  const Real dx = solver.operators().spacing();
  // The CFL step, rounded to hit t_end, and shortened where the stability limit (which moves
  // with the particles and the velocity) asks for less.
  check<ConfigError>(std::isfinite(o.dt) && o.dt >= 0, "flow: the time step must be finite and >= 0, got ", o.dt);
  const Real dt_target = o.dt > 0 ? o.dt : o.cfl * dx / vortex.max_speed(0);
  detail::check_study_length("flow", o.t_end, dt_target);
  // The errors are relative to the exact field, which decays like e^{bt}: once that is below
  // round-off (b t < ln 1e-12) they measure nothing, and below the smallest double they were inf.
  const Real decay = vortex.decay_rate() * o.t_end;
  check<ConfigError>(decay > std::log(1e-12), "flow: at Re = ", vortex.Re, " the vortex decays by e^", decay,
                     " by t = ", o.t_end, ", below round-off: the relative errors would measure nothing (a larger "
                     "Re or an earlier t_end)");
  // At least one step: a run shorter than one CFL step is that one step (the count was 0 and the
  // step -inf for t_end < 1e-9 dt_target).
  const Real dt_cfl = o.t_end / std::max(1.0, std::ceil(o.t_end / dt_target - 1e-9));
  VortexRunRow row;
  row.nx = o.cloud.nx;
  row.particles = static_cast<Index>(solver.positions().size());
  row.dt = dt_cfl;
  row.min_spacing = solver.last().min_spacing;
  row.max_spacing = solver.last().max_spacing;
  row.min_support_isotropy = solver.last().min_support_isotropy;
  row.warm_start = solver.options().warm_start.value_or(true);
  row.support_growth = solver.options().support_growth;
  const Stopwatch watch;
  detail::StepCosts costs;
  while (solver.time() < o.t_end * (1 - 1e-12)) {
    const Real dt = detail::next_study_step(solver, "flow", o.dt > 0 ? dt_cfl : 0, dt_cfl, o.t_end, costs.steps, row.dt,
                                            "try another gradient, a smaller --cfl or shifting");
    const FlowStepReport& r = solver.step(dt);
    costs.add(r);
    row.dt = std::min(row.dt, dt);
    row.min_spacing = std::min(row.min_spacing, r.min_spacing);
    row.max_spacing = std::max(row.max_spacing, r.max_spacing);
    row.min_support_isotropy = std::min(row.min_support_isotropy, r.min_support_isotropy);
    row.max_support_growth = std::max(row.max_support_growth, r.max_support_growth);
    if (o.on_step) o.on_step(solver);
  }
  costs.write(row, watch.seconds());
  row.t = solver.time();
  row.max_div_u = solver.last().max_div_u;
  row.kinetic_energy = solver.last().kinetic_energy;
  row.errors = vortex_errors(vortex, solver.positions(), solver.velocity(), solver.pressure(), solver.time());
  return row;
}

}  // namespace vrsph
