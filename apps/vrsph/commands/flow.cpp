// SPDX-License-Identifier: BSD-3-Clause
// `vrsph flow`: incompressible flow on particles by a projection per Runge–Kutta stage
// (flow/flow_solver.hpp), and its convergence studies (flow/flow_study.hpp):
//  --case taylor-green  the periodic vortex (2D Taylor–Green, 3D Beltrami) run to --t-end, one row
//                       per method and --nx, with the ISPH literature's error measures and orders;
//  --case projection    the frozen-cloud projection of u_exact + ∇φ (no time stepping);
//  --case cavity        the lid-driven cavity run to a steady state (Eulerian, or Lagrangian
//                       with its profiles averaged), its centre lines against Ghia, Ghia & Shin
//                       (1982) (flow/cavity.hpp);
//  --case hydrostatic   water at rest in a tank under gravity, with a free surface
//                       (flow_free_surface.cpp, flow/tank.hpp);
//  --case dam-break     a water column released in a tank, its surge front against Martin &
//                       Moyce's experiments and Koshizuka & Oka's MPS (flow/dam_break.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/support_isotropy.hpp>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/cavity.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/flow_study.hpp>
#include <vrsph/flow/ghia.hpp>
#include <vrsph/io/output_file.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#include "../problem_file.hpp"
#include "../vtu_series.hpp"
#include "flow_args.hpp"

namespace vrsph::cli {

FlowCloudSpec cloud_spec(const FlowArgs& a, int nx) {
  check<ConfigError>(a.cloud == "perturbed" || a.cloud == "lattice", "--cloud for flow is perturbed or lattice, got ", a.cloud);
  FlowCloudSpec c;
  c.dim = a.dim;
  c.nx = nx;
  c.jitter = a.cloud == "lattice" ? 0.0 : a.jitter;
  c.seed = a.seed;
  return c;
}

std::unique_ptr<VtuSeries> series_for(const FlowArgs& a, const std::vector<std::string>& methods,
                                      const std::vector<int>& nxs, const std::string& method, int nx) {
  if (a.vtu_series.empty() || method != methods.front() || nx != nxs.back()) return nullptr;
  return std::make_unique<VtuSeries>(a.vtu_series);
}

PointField isotropy_field(const FlowSolver& s) {
  return {"support_isotropy", Eigen::MatrixXd(support_isotropy(s.operators().cloud(), s.operators().neighbours()))};
}

// The method of `method`'s first-derivative rows in a flow when it is another one (flow_operators:
// auto pairs VRSPH with FPM), else empty.
std::string gradient_method_of(const std::string& gradient, const std::string& method) {
  if (gradient == "own") return {};
  if (gradient == "auto") return method == "vrsph" ? "fpm" : "";
  return gradient == method ? "" : gradient;
}

OperatorsOptions operators_for(const FlowArgs& a, const std::string& method,
                               const std::map<std::string, MethodOptions>& options) {
  OperatorsOptions o;
  o.method = method;
  o.method_options = options_for(options, method);
  if (const std::string g = gradient_method_of(a.gradient, method); !g.empty())
    o.gradient_method_options = options_for(options, g);
  o.h_factor = a.h_factor;
  o.kernel = parse_kernel(a.kernel);
  return o;
}



void skip_orders(std::map<std::string, std::vector<Real>>& errors) {
  for (auto& [name, e] : errors) e.push_back(std::numeric_limits<Real>::quiet_NaN());
}

FlowOptions flow_options_for(const FlowArgs& a, const std::string& method,
                             const std::map<std::string, MethodOptions>& options) {
  FlowOptions o;
  o.frame = parse_flow_frame(a.frame);
  o.scheme = parse_flow_scheme(a.scheme);
  o.viscosity = parse_flow_viscosity(a.viscosity);
  o.operators = operators_for(a, method, options);
  o.gradient = a.gradient;
  o.solver.type = parse_solver(a.solver);
  o.allow_unstable = a.allow_unstable;
  o.reuse_factorisation = a.reuse_factorisation;
  o.reuse_hierarchy = a.reuse_hierarchy;
  o.pressure_corrections = a.pressure_corrections;
  o.hyperviscosity = a.hyperviscosity;
  o.shifting = {parse_shifting(a.shifting), a.shift_coefficient, a.shift_limit};
  o.support_growth = a.support_growth;
  o.support_isotropy_target = a.support_isotropy;
  if (a.warm_start != "auto") o.warm_start = a.warm_start == "on";
  o.wall_acceleration = parse_wall_acceleration(a.wall_acceleration);
  o.surface_gradient = parse_surface_gradient(a.surface_gradient);
  o.surface.film_eigenvalue = a.surface_film;
  if (a.wall_gap) o.wall_gap = *a.wall_gap;
  return o;
}

void add_orders(Table& t, std::size_t first, const std::vector<int>& nx, const std::map<std::string, std::vector<Real>>& errors) {
  std::vector<Real> h;
  for (const int n : nx) h.push_back(1.0 / n);
  for (const auto& [name, e] : errors) {
    const std::vector<Real> orders = pairwise_orders(h, e);
    const auto col = static_cast<std::size_t>(std::find(t.columns.begin(), t.columns.end(), name) - t.columns.begin());
    for (std::size_t k = 1; k < orders.size(); ++k)
      if (std::isfinite(orders[k])) t.rows[first + k][col] = TableCell(orders[k]);
  }
}

namespace {

const std::vector<std::string> projection_columns = {
    "case", "method", "gradient", "dim", "nx", "particles", "error_u_inf", "error_u_l2", "error_gradp_inf",
    "error_phi_inf", "max_div_before", "max_div_after", "order_u_inf", "order_u_l2", "order_phi_inf",
    "solver_iterations", "seconds"};
const std::vector<std::string> taylor_green_columns = {
    "case", "method", "gradient", "pressure_corrections", "frame", "scheme", "viscosity", "volumes", "support_growth", "dim", "nx", "particles",
    "t", "steps", "dt", "error_u_mean", "error_u_inf", "error_p_mean", "error_p_inf", "decay_rate_error", "max_div_u",
    "order_u_mean", "order_u_inf", "order_p_mean", "kinetic_energy", "min_spacing", "max_spacing",
    "min_support_isotropy", "max_support_growth", "ppe_iterations_per_step", "seconds_per_step", "seconds_update", "seconds_ppe", "seconds_rhs", "seconds_viscous", "status"};

const std::vector<std::string> cavity_columns = {
    "case", "method", "gradient", "pressure_corrections", "frame", "re", "nx", "particles", "t", "steps", "dt", "steady", "steady_residual",
    "average_time", "profile_fluctuation", "wall_pushes", "ghia_max_deviation_u", "ghia_max_deviation_v", "order_ghia_u", "order_ghia_v", "reference_max_deviation_u",
    "reference_max_deviation_v", "order_reference_u", "order_reference_v", "max_div_u", "kinetic_energy",
    "ppe_iterations_per_step", "seconds_setup", "seconds_per_step", "seconds_ppe", "seconds_rhs", "seconds_viscous", "status"};

void run_projection(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                    const std::map<std::string, MethodOptions>& options) {
  Table t;
  t.columns = projection_columns;
  SolverOptions so = pressure_solver_defaults();
  so.type = parse_solver(a.solver);
  Progress progress;
  std::size_t done = 0;
  for (const std::string& m : methods) {
    const std::size_t first = t.rows.size();
    std::map<std::string, std::vector<Real>> errors;
    for (const int n : nxs) {
      progress.update(detail::concat(m, " nx = ", n), static_cast<double>(done++) / static_cast<double>(methods.size() * nxs.size()));
      FlowOptions fo;
      fo.operators = operators_for(a, m, options);
      fo.gradient = a.gradient;
      const OperatorsOptions ops = flow_operators(fo);
      const ProjectionStudyRow r = frozen_projection(cloud_spec(a, n), ops, so);
      errors["order_u_inf"].push_back(r.error_u_inf);
      errors["order_u_l2"].push_back(r.error_u_l2);
      errors["order_phi_inf"].push_back(r.error_phi_inf);
      t.add_row({{"case", std::string("projection")}, {"method", m},
                 {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method}, {"dim", static_cast<long long>(a.dim)},
                 {"nx", static_cast<long long>(n)}, {"particles", static_cast<long long>(r.particles)},
                 {"error_u_inf", r.error_u_inf}, {"error_u_l2", r.error_u_l2}, {"error_gradp_inf", r.error_gradp_inf},
                 {"error_phi_inf", r.error_phi_inf}, {"max_div_before", r.max_div_before}, {"max_div_after", r.max_div_after},
                 {"solver_iterations", static_cast<long long>(r.iterations)}, {"seconds", r.seconds}});
    }
    add_orders(t, first, nxs, errors);
  }
  Json extra;
  extra["case"] = "projection";
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  emit(t, a.out, extra, "nx", "error_u_inf:-1/-2", "method", "frozen-cloud projection: max velocity error");
}

void run_taylor_green(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                      const std::map<std::string, MethodOptions>& options) {
  Table t;
  t.columns = taylor_green_columns;
  Progress progress;
  std::size_t done = 0;
  const double runs = static_cast<double>(methods.size() * nxs.size());
  FailedRuns failed;
  FlowHistory history(a.history);
  for (const std::string& m : methods) {
    const std::size_t first = t.rows.size();
    std::map<std::string, std::vector<Real>> errors{{"order_u_mean", {}}, {"order_u_inf", {}}, {"order_p_mean", {}}};
    for (const int n : nxs) {
      VortexRunOptions o;
      o.cloud = cloud_spec(a, n);
      o.vortex.Re = a.re;
      o.t_end = a.t_end;
      o.cfl = a.cfl;
      o.dt = a.dt;
      o.flow = flow_options_for(a, m, options);
      PeriodicVortex vortex = o.vortex;
      vortex.dim = a.dim;
      std::unique_ptr<VtuSeries> series = series_for(a, methods, nxs, m, n);
      const double index = static_cast<double>(done++);
      std::string first_warning;
      Index warned = 0;
      o.on_step = [&](const FlowSolver& s) {
        for (const std::string& w : s.last().warnings) {
          if (first_warning.empty()) first_warning = w;
          ++warned;
        }
        progress.update(detail::concat(m, " nx = ", n, " t = ", s.time()), (index + s.time() / a.t_end) / runs);
        if (history.on()) {
          const VortexErrors e = vortex_errors(vortex, s.positions(), s.velocity(), s.pressure(), s.time());
          history.record("taylor-green", m, n, s,
                         {{"error_u_mean", e.error_u_mean}, {"error_u_inf", e.error_u_inf},
                          {"error_p_mean", e.error_p_mean}, {"decay_rate_error", e.decay_rate_error}});
        }
        const bool last = s.time() >= a.t_end * (1 - 1e-12);
        if (series && (last || (a.vtu_every > 0 && s.steps() % a.vtu_every == 0))) {
          series->write(s.time(), s.operators().cloud(),
                        {{"velocity", s.velocity()}, {"pressure", Eigen::MatrixXd(s.pressure())}, isotropy_field(s)});
        }
      };
      VortexRunRow r;
      if (!failed.attempt(t, {{"case", std::string("taylor-green")}, {"method", m}, {"nx", static_cast<long long>(n)}},
                          [&] { r = run_periodic_vortex(o); })) {
        skip_orders(errors);
        continue;
      }
      if (warned > 0 && communicator().rank() == 0)
        std::cerr << "vrsph: warning: " << first_warning << (warned > 1 ? detail::concat(" (and ", warned - 1, " more)") : "") << '\n';
      errors["order_u_mean"].push_back(r.errors.error_u_mean);
      errors["order_u_inf"].push_back(r.errors.error_u_inf);
      errors["order_p_mean"].push_back(r.errors.error_p_mean);
      const OperatorsOptions ops = flow_operators(o.flow);
      t.add_row({{"case", std::string("taylor-green")}, {"method", m},
                 {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method},
                 {"pressure_corrections", static_cast<long long>(pressure_corrections_for(o.flow))}, {"frame", a.frame},
                 {"scheme", a.scheme}, {"viscosity", a.viscosity},
                 {"volumes", std::string(r.warm_start ? "warm" : "cold")}, {"support_growth", r.support_growth}, {"dim", static_cast<long long>(a.dim)}, {"nx", static_cast<long long>(n)},
                 {"particles", static_cast<long long>(r.particles)}, {"t", r.t}, {"steps", static_cast<long long>(r.steps)},
                 {"dt", r.dt}, {"error_u_mean", r.errors.error_u_mean}, {"error_u_inf", r.errors.error_u_inf},
                 {"error_p_mean", r.errors.error_p_mean}, {"error_p_inf", r.errors.error_p_inf},
                 {"decay_rate_error", r.errors.decay_rate_error}, {"max_div_u", r.max_div_u},
                 {"kinetic_energy", r.kinetic_energy}, {"min_spacing", r.min_spacing}, {"max_spacing", r.max_spacing},
                 {"min_support_isotropy", r.min_support_isotropy}, {"max_support_growth", r.max_support_growth},
                 {"ppe_iterations_per_step", r.ppe_iterations_per_step}, {"seconds_per_step", r.seconds_per_step},
                 {"seconds_update", r.seconds_update}, {"seconds_ppe", r.seconds_ppe}, {"seconds_rhs", r.seconds_rhs}, {"seconds_viscous", r.seconds_viscous},
                 {"status", std::string("ok")}});
    }
    add_orders(t, first, nxs, errors);
  }
  Json extra;
  extra["case"] = "taylor-green";
  extra["exact_solution"] = a.dim == 2 ? "Taylor-Green vortex" : "Beltrami (ABC) flow";
  extra["re"] = a.re;
  extra["t_end"] = a.t_end;
  extra["cfl"] = a.cfl;
  extra["shifting"] = a.shifting;
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  extra["peak_memory_mib"] = peak_memory_mib();
  history.write();
  emit(t, a.out, extra, "nx", "error_u_mean:-1/-2,error_p_mean:-1/-2", "method", "Taylor-Green: mean velocity and pressure errors");
  failed.raise_if_any();
}

// The centre-line profiles in long form: series (method and nx, or ghia), line, coordinate, value.
std::string profile_csv(const std::vector<std::pair<std::string, CavityRunRow>>& runs, Real re) {
  std::string out = "series,line,s,value\n";
  const auto add = [&out](const std::string& series, const char* line, Real at, Real value) {
    out += detail::concat(series, ',', line, ',', at, ',', value, '\n');
  };
  for (const auto& [series, r] : runs)
    for (std::size_t k = 0; k < r.line.size(); ++k) {
      add(series, "u(0.5;y)", r.line[k], r.u_line[k]);
      add(series, "v(x;0.5)", r.line[k], r.v_line[k]);
    }
  const GhiaProfiles& g = ghia_profiles(re);
  for (std::size_t k = 0; k < g.y.size(); ++k) add("ghia", "u(0.5;y)", g.y[k], g.u[k]);
  for (std::size_t k = 0; k < g.x.size(); ++k) add("ghia", "v(x;0.5)", g.x[k], g.v[k]);
  for (std::size_t k = 0; k < g.y.size(); ++k) add("p2-p1 n=128", "u(0.5;y)", g.y[k], g.u_converged[k]);
  for (std::size_t k = 0; k < g.x.size(); ++k) add("p2-p1 n=128", "v(x;0.5)", g.x[k], g.v_converged[k]);
  return out;
}

void run_cavity_case(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                     const std::map<std::string, MethodOptions>& options) {
  check<ConfigError>(a.dim == 2, "the cavity is two-dimensional (--dim 2), got --dim ", a.dim);
  (void)ghia_profiles(a.re);  // Re 100 or 1000, before a long run
  check<ConfigError>(std::isfinite(a.steady_tol) && a.steady_tol > 0, "--steady-tol must be positive, got ", a.steady_tol);
  const Real t_end = a.t_end > 0 ? a.t_end : 100;
  Table t;
  t.columns = cavity_columns;
  Progress progress;
  std::size_t done = 0;
  const double runs = static_cast<double>(methods.size() * nxs.size());
  std::vector<std::pair<std::string, CavityRunRow>> profiles;
  FailedRuns failed;
  FlowHistory history(a.history);
  for (const std::string& m : methods) {
    const std::size_t first = t.rows.size();
    std::map<std::string, std::vector<Real>> errors{
        {"order_ghia_u", {}}, {"order_ghia_v", {}}, {"order_reference_u", {}}, {"order_reference_v", {}}};
    for (const int n : nxs) {
      CavityRunOptions o;
      o.cloud.nx = n;
      o.cloud.jitter = a.cloud == "lattice" ? 0.0 : a.jitter;
      o.cloud.seed = a.seed;
      o.cloud.wall_layers = a.wall_layers;
      if (a.wall_gap) o.lagrangian_wall_gap = *a.wall_gap;
      o.re = a.re;
      o.t_end = t_end;
      o.cfl = a.cfl;
      o.dt = a.dt;
      o.steady_tolerance = a.steady_tol;
      o.flow = flow_options_for(a, m, options);
      std::unique_ptr<VtuSeries> series = series_for(a, methods, nxs, m, n);
      const double index = static_cast<double>(done++);
      o.on_step = [&](const FlowSolver& s, Real residual) {
        progress.update(detail::concat(m, " nx = ", n, " t = ", s.time(), " steady residual ", residual),
                        (index + s.time() / t_end) / runs);
        history.record("cavity", m, n, s, {{"steady_residual", residual}});
        const bool last = residual < a.steady_tol || s.time() >= t_end * (1 - 1e-12);
        if (series && (last || (a.vtu_every > 0 && s.steps() % a.vtu_every == 0)))
          series->write(s.time(), s.operators().cloud(),
                        {{"velocity", s.velocity()}, {"pressure", Eigen::MatrixXd(s.pressure())}, isotropy_field(s)});
      };
      CavityRunRow r;
      if (!failed.attempt(t, {{"case", std::string("cavity")}, {"method", m}, {"nx", static_cast<long long>(n)}},
                          [&] { r = run_cavity(o); })) {
        skip_orders(errors);
        continue;
      }
      if (!r.steady && communicator().rank() == 0)
        std::cerr << "vrsph: warning: " << m << " nx = " << n << " did not reach a steady state by t = " << r.t
                  << (std::isnan(r.steady_residual)
                          ? std::string(" (too short a run for two windows of its samples)")
                          : detail::concat(" (residual ", r.steady_residual, " > --steady-tol ", a.steady_tol, ")"))
                  << "; the profiles are "
                  << (r.average_time > 0 ? detail::concat("the mean over its last ", r.average_time, " time units (their "
                                                          "samples fluctuate by ", r.profile_fluctuation, ")")
                                         : std::string("those at the end"))
                  << "\n";
      errors["order_ghia_u"].push_back(r.ghia_max_deviation_u);
      errors["order_ghia_v"].push_back(r.ghia_max_deviation_v);
      errors["order_reference_u"].push_back(r.reference_max_deviation_u);
      errors["order_reference_v"].push_back(r.reference_max_deviation_v);
      const OperatorsOptions ops = flow_operators(o.flow);
      t.add_row({{"case", std::string("cavity")}, {"method", m},
                 {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method},
                 {"pressure_corrections", static_cast<long long>(pressure_corrections_for(o.flow))}, {"frame", a.frame}, {"re", a.re},
                 {"nx", static_cast<long long>(n)}, {"particles", static_cast<long long>(r.particles)}, {"t", r.t},
                 {"steps", static_cast<long long>(r.steps)}, {"dt", r.dt}, {"steady", r.steady},
                 {"steady_residual", r.steady_residual}, {"average_time", r.average_time},
                 {"profile_fluctuation", r.profile_fluctuation},
                 {"wall_pushes", static_cast<long long>(r.wall_pushes)},
                 {"ghia_max_deviation_u", r.ghia_max_deviation_u},
                 {"ghia_max_deviation_v", r.ghia_max_deviation_v},
                 {"reference_max_deviation_u", r.reference_max_deviation_u},
                 {"reference_max_deviation_v", r.reference_max_deviation_v}, {"max_div_u", r.max_div_u},
                 {"kinetic_energy", r.kinetic_energy}, {"ppe_iterations_per_step", r.ppe_iterations_per_step},
                 {"seconds_setup", r.seconds_setup}, {"seconds_per_step", r.seconds_per_step},
                 {"seconds_ppe", r.seconds_ppe}, {"seconds_rhs", r.seconds_rhs}, {"seconds_viscous", r.seconds_viscous}, {"status", std::string("ok")}});
      profiles.emplace_back(detail::concat(m, " nx=", n), r);
    }
    add_orders(t, first, nxs, errors);
  }
  history.write();
  if (!a.profile_output.empty() && communicator().rank() == 0) {
    const std::string csv = profile_csv(profiles, a.re);
    write_file(a.profile_output, "centre-line profiles", [&csv](std::ostream& f) { f << csv; });
  }
  Json extra;
  extra["case"] = "cavity";
  extra["reference"] = "Ghia, Ghia & Shin, J. Comput. Phys. 48 (1982) 387-411, Tables I-II";
  extra["converged_reference"] = "Taylor-Hood P2-P1, 128 x 128 crossed cells (scripts/cavity_reference.py)";
  extra["re"] = a.re;
  extra["t_end"] = t_end;
  extra["steady_tolerance"] = a.steady_tol;
  extra["cfl"] = a.cfl;
  extra["frame"] = a.frame;
  extra["shifting"] = a.shifting;
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  extra["peak_memory_mib"] = peak_memory_mib();
  emit(t, a.out, extra, "nx",
       "ghia_max_deviation_u:-1/-2,ghia_max_deviation_v:-1/-2,reference_max_deviation_u,reference_max_deviation_v",
       "method", "lid-driven cavity: largest centre-line deviation from Ghia et al. and a converged solution");
  failed.raise_if_any();
}

void run_flow(FlowArgs& a) {
  validate_output(a.out);
  set_thread_count(a.threads);
  check<ConfigError>(a.dim == 2 || a.dim == 3, "--dim for flow must be 2 or 3, got ", a.dim);
  check<ConfigError>(a.flow_case == "taylor-green" || a.flow_case == "projection" || a.flow_case == "cavity" ||
                         a.flow_case == "hydrostatic" || a.flow_case == "dam-break",
                     "unknown --case '", a.flow_case, "' (known: taylor-green, projection, cavity, hydrostatic, dam-break)");
  const bool hydrostatic = a.flow_case == "hydrostatic", dam_break = a.flow_case == "dam-break";
  for (const auto& [value, name] : {std::pair{a.gravity != 1, "--gravity"}, {a.ramp != -1, "--ramp"},
                                    {a.depth != 0, "--depth"}, {a.tank_width != 0, "--tank-width"},
                                    {a.wall_height != 0, "--wall-height"}})
    check<ConfigError>(hydrostatic || !value, name, " applies to --case hydrostatic");
  if ((hydrostatic || dam_break) && !a.frame_given) a.frame = "lagrangian";
  if (dam_break && !a.shifting_given) a.shifting = "xu";
  check<ConfigError>(std::isfinite(a.t_end) && a.t_end >= 0, "--t-end must be finite and > 0 (0: the case's default), got ",
                     a.t_end);
  check<ConfigError>(a.profile_output.empty() || a.flow_case == "cavity", "--profile-output applies to --case cavity only");
  check<ConfigError>(a.history.empty() || a.flow_case != "projection", "--history applies to the cases that step in time "
                     "(the projection case has no steps)");
  check<ConfigError>(a.wall_layers == 0 || a.flow_case == "cavity" || hydrostatic || dam_break,
                     "--wall-layers applies to the cases with walls (cavity, hydrostatic, dam-break)");
  check<ConfigError>(a.geometry == "martin-moyce" || dam_break, "--geometry applies to the dam break (--case dam-break)");
  (void)parse_wall_acceleration(a.wall_acceleration);
  check<ConfigError>(a.wall_acceleration == "momentum" || dam_break || hydrostatic, "--wall-acceleration applies to the "
                     "free-surface cases (hydrostatic, dam-break)");
  (void)parse_surface_gradient(a.surface_gradient);
  check<ConfigError>(a.surface_gradient == "linear" || dam_break || hydrostatic, "--surface-gradient applies to the "
                     "free-surface cases (hydrostatic, dam-break)");
  check<ConfigError>(a.surface_film == 0.1 || dam_break || hydrostatic, "--surface-film applies to the free-surface cases "
                     "(hydrostatic, dam-break)");
  check<ConfigError>(std::isfinite(a.surface_film) && a.surface_film >= 0 && a.surface_film < 1,
                     "--surface-film must be in [0, 1) (0: off), got ", a.surface_film);
  (void)parse_dam_break_geometry(a.geometry);
  check<ConfigError>(!a.wall_gap || (std::isfinite(*a.wall_gap) && *a.wall_gap >= 0 && *a.wall_gap < 1),
                     "--wall-gap must be in [0, 1) particle spacings, got ", a.wall_gap.value_or(0));
  check<ConfigError>(!a.wall_gap || a.frame == "lagrangian", "--wall-gap applies to the lagrangian frame (particles "
                     "that move)");
  check<ConfigError>(a.wall_layers >= 0 && a.wall_layers <= 8, "--wall-layers must be in [1, 8] (0: the case's own), got ",
                     a.wall_layers);
  const std::vector<std::string> methods = parse_name_list(a.methods, "--method");
  const std::vector<int> nxs = parse_int_list(a.nx, "--nx");
  for (const int n : nxs) {
    check<ConfigError>(n >= 4 && n <= 4096, "--nx values must be in [4, 4096], got ", n);
    check<ConfigError>(std::pow(static_cast<double>(n), a.dim) <= 2e7, "--nx ", n, " in ", a.dim, "D is over 2e7 particles");
  }
  (void)parse_flow_frame(a.frame);
  (void)parse_flow_scheme(a.scheme);
  check<ConfigError>(parse_flow_viscosity(a.viscosity) == FlowViscosity::Explicit || a.flow_case != "projection",
                     "--viscosity implicit applies to the cases that take time steps; --case projection takes none");
  const SolverType solver = parse_solver(a.solver);
  check<ConfigError>(!a.reuse_factorisation || solver == SolverType::Auto || solver == SolverType::UmfPack ||
                         solver == SolverType::SparseLU,
                     "--reuse-factorisation reuses a direct solver's factorisation; --solver ", a.solver,
                     " has none (give umfpack, sparselu or auto)");
  check<ConfigError>(!a.reuse_factorisation || a.frame == "lagrangian", "--reuse-factorisation applies to the "
                     "lagrangian frame (the eulerian one factorises its pressure matrix once)");
  (void)parse_kernel(a.kernel);
  (void)parse_shifting(a.shifting);
  check<ConfigError>(std::isfinite(a.support_growth) && (a.support_growth >= 1 || a.support_growth == 0),
                     "--support-growth must be finite and >= 1 (1: fixed supports; 0: automatic), got ", a.support_growth);
  check<ConfigError>(a.support_growth <= 1 || a.frame == "lagrangian", "--support-growth applies to the lagrangian frame "
                     "(an eulerian cloud does not move)");
  check<ConfigError>(std::isfinite(a.support_isotropy) && a.support_isotropy > 0 && a.support_isotropy <= 0.5,
                     "--support-isotropy must be in (0, 0.5], got ", a.support_isotropy);
  check<ConfigError>(a.warm_start == "auto" || a.warm_start == "on" || a.warm_start == "off",
                     "--warm-start must be auto, on or off, got '", a.warm_start, "'");
  check<ConfigError>(a.vtu_every >= 0, "--vtu-every must be >= 0");
  // --method-opt METHOD:key=value also reaches the flows' gradient method (--gradient fpm, or
  // auto's fpm beside vrsph) when it is not one of --method; key=value alone stays with --method's.
  std::vector<std::string> gradient_only, own_items, gradient_items;
  for (const auto& m : methods)
    if (const std::string g = gradient_method_of(a.gradient, m);
        !g.empty() && std::find(methods.begin(), methods.end(), g) == methods.end() &&
        std::find(gradient_only.begin(), gradient_only.end(), g) == gradient_only.end())
      gradient_only.push_back(g);
  for (const auto& item : a.method_opts) {
    const auto colon = item.find(':');
    const bool to_gradient = colon != std::string::npos && colon < item.find('=') &&
                             std::find(gradient_only.begin(), gradient_only.end(), item.substr(0, colon)) != gradient_only.end();
    (to_gradient ? gradient_items : own_items).push_back(item);
  }
  auto options = parse_method_options(own_items, methods);
  options.merge(parse_method_options(gradient_items, gradient_only));
  validate_columns(a.out, a.flow_case == "projection" ? projection_columns
                         : a.flow_case == "cavity"   ? cavity_columns
                         : hydrostatic               ? hydrostatic_columns
                         : dam_break                 ? dam_break_columns
                                                     : taylor_green_columns);
  if (a.flow_case == "projection") return run_projection(a, methods, nxs, options);
  if (a.flow_case == "cavity") return run_cavity_case(a, methods, nxs, options);
  if (hydrostatic) return run_hydrostatic_case(a, methods, nxs, options);
  if (dam_break) return run_dam_break_case(a, methods, nxs, options);
  if (a.t_end == 0) a.t_end = 1;
  run_taylor_green(a, methods, nxs, options);
}

}  // namespace

void add_flow_command(CLI::App& app) {
  auto a = std::make_shared<FlowArgs>();
  auto* cmd = app.add_subcommand("flow", "Incompressible flow on particles (projection per Runge-Kutta stage): the "
                                         "Taylor-Green vortex, the frozen-cloud projection and the lid-driven cavity, "
                                         "with errors and orders");
  cmd->add_option("--case", a->flow_case, "taylor-green (2D Taylor-Green, 3D Beltrami vortex) | projection (frozen cloud) | "
                                         "cavity (lid-driven, against Ghia et al. 1982) | hydrostatic (water at rest "
                                         "in a tank, free surface) | dam-break (a column released, against Martin & "
                                         "Moyce 1952 and Koshizuka & Oka 1996)")
      ->capture_default_str();
  cmd->add_option("--dim", a->dim, "Dimension 2 or 3")->capture_default_str();
  cmd->add_option("--frame", a->frame, "eulerian (a fixed cloud) | lagrangian (particles move with the flow)")->capture_default_str();
  cmd->add_option("--method", a->methods, "Methods for the Laplacian (pressure Poisson, viscous term), comma-separated")
      ->capture_default_str();
  cmd->add_option("--gradient", a->gradient, "First derivatives: auto (vrsph: fpm gradient_order=2; others: own) | own | "
                                             "a method name")->capture_default_str();
  cmd->add_option("--method-opt", a->method_opts, "key=value or method:key=value options of the methods (method: also "
                  "the gradient's method, e.g. fpm:gradient_order=3 beside vrsph)");
  cmd->add_option("--nx", a->nx, "Particles per unit period along each axis (cavity: intervals per side; hydrostatic: across the tank; dam-break: across the column), "
                                 "comma-separated (a refinement)")->capture_default_str();
  cmd->add_option("--cloud", a->cloud, "perturbed (a jittered lattice) | lattice")->capture_default_str();
  cmd->add_option("--jitter", a->jitter, "Perturbation U(-j dx, j dx) per coordinate")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius h = h_factor * dx")->capture_default_str();
  cmd->add_option("--kernel", a->kernel, "Kernel")->capture_default_str();
  cmd->add_option("--re", a->re, "Reynolds number U L / nu (L = 1, U = 1; cavity: 100 or 1000; hydrostatic: "
                                 "(g H)^(1/2) H / nu)")->capture_default_str();
  cmd->add_option("--gravity", a->gravity, "Hydrostatic: |g| (down the last axis)")->capture_default_str();
  cmd->add_option("--ramp", a->ramp, "Hydrostatic: gravity reaches |g| over this time (default 0.5 (H/g)^(1/2))");
  cmd->add_option("--depth", a->depth, "Hydrostatic: the water's depth H (default: the tank's width)");
  cmd->add_option("--tank-width", a->tank_width, "Hydrostatic: the tank's width (default 1; --nx intervals across it)");
  cmd->add_option("--wall-height", a->wall_height, "Hydrostatic: the walls' height, a whole number of spacings at least the "
                  "water's depth (default: the depth, walls ending at the water's level)");
  cmd->add_option("--wall-acceleration", a->wall_acceleration, "Free surfaces: the acceleration the walls' extrapolated "
                  "pressure carries from the water: momentum (nu lap u + g at the wall) | body-force (g alone, Adami et al. "
                  "2012: runs a dam break through its impact on the far wall at nx <= 20)")
      ->capture_default_str();
  cmd->add_option("--surface-gradient", a->surface_gradient, "Free surfaces, with a least-squares gradient above linear "
                  "order (auto beside vrsph: fpm gradient_order=2): linear (that fit's linear form at the surface "
                  "particles without a wall neighbour, whose supports only the air cuts; holds a tank at rest for 20 s at "
                  "nx = 10) | same (the higher order there too, as before 2026-12-06)")
      ->capture_default_str();
  cmd->add_option("--surface-film", a->surface_film, "Free surfaces: a water particle whose water neighbours alone (walls "
                  "left out) give a smallest renormalisation eigenvalue below this is surface, its normal across them: a "
                  "jet one particle thick running up a wall (0: off, the walls then make it look half full), in [0, 1)")
      ->capture_default_str();
  cmd->add_option("--geometry", a->geometry, "Dam-break: martin-moyce (column L x 2L, tank 4L, fronts against Martin & "
                  "Moyce and Koshizuka & Oka) | buchner (column 2H x H, tank 5.366H, the far wall's pressure at probe P1 "
                  "against Buchner 2002; --nx intervals across H, --re = (g H)^(1/2) H / nu)")
      ->capture_default_str();
  cmd->add_option("--t-end", a->t_end, "End time (0: 1 for taylor-green; cavity: 100, the run stops when steady; "
                                       "hydrostatic: 2; dam-break: 2.5 (L/g)^(1/2), T = 3.54; --geometry buchner: 8 (H/g)^(1/2))")
      ->capture_default_str();
  cmd->add_option("--wall-layers", a->wall_layers, "Cavity, hydrostatic, dam-break: layers of wall particles, 1-8 (0: "
                  "the case's own: cavity 1 eulerian and 3 lagrangian, hydrostatic 1, dam-break 3)")
      ->capture_default_str();
  cmd->add_option("--wall-gap", a->wall_gap, "Lagrangian, walls: a particle that ends a step closer than this many "
                  "spacings to a wall face is reflected off the plane at that distance (0: never; default: 0.5 for the "
                  "cavity and the dam break, 0 otherwise)");
  cmd->add_option("--steady-tol", a->steady_tol, "Cavity: steady when max |u(n+1) - u(n)| / dt < this (lagrangian: the "
                  "same of the means of the centre lines' samples, every 0.5 time units, over the last two windows of 10, "
                  "or those means equal within twice their standard error)")
      ->capture_default_str();
  cmd->add_option("--profile-output", a->profile_output, "Cavity: the centre-line profiles (and Ghia's points) as CSV");
  cmd->add_option("--history", a->history, "Every step of every run as a row (FILE.csv, .json or .md): energy, max |div u|, "
                  "CFL and viscous numbers, PPE iterations, spacing and support isotropy, shifting, costs; Taylor-Green: "
                  "its errors after each step. Written also when a run blows up (the steps before it)");
  cmd->add_option("--cfl", a->cfl, "dt = cfl dx / U, shortened where the stability limit asks for less")->capture_default_str();
  cmd->add_option("--dt", a->dt, "A fixed time step instead of --cfl (refused beyond the stability limit unless "
                                 "--allow-unstable)");
  cmd->add_option("--scheme", a->scheme, "rk3 (SSP, third order) | rk2 (Heun), a projection per stage")->capture_default_str();
  cmd->add_option("--viscosity", a->viscosity,
                  "explicit (in the Runge-Kutta rate; dt limited like dx^2/nu) | implicit (IMEX: ARS(4,4,3) with rk3, "
                  "ARS(2,2,2) with rk2; one (I - a dt nu L) solve per stage and component, dt limited by the explicit terms)")
      ->capture_default_str();
  cmd->add_option("--hyperviscosity", a->hyperviscosity, "Eulerian: -c U dx^3 L(L u) added (0: none)")->capture_default_str();
  cmd->add_option("--shifting", a->shifting, "Lagrangian particle shifting: none | xu (Xu 2009) | lind (Lind 2012, "
                                             "Fickian)")->capture_default_str();
  cmd->add_option("--support-growth", a->support_growth,
                  "Lagrangian: every support grows (by 15 % a step, up to this times h) while the smallest support "
                  "isotropy is below --support-isotropy, and shrinks back once it is above twice that; 1: fixed supports; "
                  "0: automatic (up to 9 spacings, capped below half the period, for a 2D lagrangian run on a periodic box without walls, "
                  "free surface or shifting; 1 elsewhere)")
      ->capture_default_str();
  cmd->add_option("--support-isotropy", a->support_isotropy, "The smallest support isotropy below which --support-growth grows the supports, "
                                                             "in (0, 0.5]")->capture_default_str();
  cmd->add_option("--warm-start", a->warm_start,
                  "Lagrangian, VRSPH: start each row's volumes from its active set of the step before: auto (off for a 2D "
                  "flow without walls, free surface or shifting, where warm rows drift to less accurate ones over many "
                  "steps; on elsewhere) | on | off")
      ->capture_default_str();
  cmd->add_option("--shift-coefficient", a->shift_coefficient, "beta (xu) or A (lind); 0: 0.04 and 2")->capture_default_str();
  cmd->add_option("--shift-limit", a->shift_limit, "The largest shift of a step, in particle spacings (0: unbounded, as "
                  "published; Xu's shift grows without bound as two particles meet)")->capture_default_str();
  cmd->add_flag("--allow-unstable", a->allow_unstable, "Warn instead of refusing a time step beyond the stability limit");
  cmd->add_option("--solver", a->solver, "Pressure Poisson solver: auto | umfpack | sparselu | bicgstab | petsc")->capture_default_str();
  cmd->add_option("--reuse-hierarchy", a->reuse_hierarchy,
                  "Lagrangian, PETSc pressure solves: an earlier stage's AMG hierarchy preconditions the next pressure "
                  "matrices while their solves take at most 1.1 times its own iterations (false: a new hierarchy every "
                  "stage; the result is the same to the solver's tolerance)")
      ->capture_default_str();
  cmd->add_option("--pressure-corrections", a->pressure_corrections,
                  "Defect corrections of every stage's pressure toward D(a - G p) = 0, the divergence of the rate the "
                  "stage uses (one more pressure solve each; 0: none, the stage's divergence then left to the end-of-step "
                  "projection, whose splitting error moves results with dt). Default: 1 with --method vrsph, 0 with the "
                  "others (with FPM's own Laplacian they raise the pressure's error; SPH and MPS keep their published scheme)");
  cmd->add_option("--reuse-factorisation", a->reuse_factorisation,
                  "Lagrangian, direct solvers: an earlier stage's factorisation preconditions BiCGSTAB on the next "
                  "pressure matrices until it needs more than 30 iterations (false: factorise every stage)")
      ->capture_default_str();
  cmd->add_option("--vtu-series", a->vtu_series, "Write velocity and pressure of the first method's finest run as "
                                                 "PREFIX_NNNN.vtu and PREFIX.pvd (the end, and every --vtu-every steps)");
  cmd->add_option("--vtu-every", a->vtu_every, "Steps between VTU files (0: the end only)")->capture_default_str();
  cmd->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "PNG plot of the error against nx");
  add_columns_option(cmd, a->out, {"method", "gradient", "pressure_corrections", "frame", "nx", "particles", "steps", "error_u_mean", "error_u_inf",
                                   "error_u_l2", "error_p_mean", "error_phi_inf", "decay_rate_error", "max_div_u",
                                   "ghia_max_deviation_u", "ghia_max_deviation_v", "reference_max_deviation_u",
                                   "reference_max_deviation_v", "steady_residual", "status",
                                   "max_div_after", "order_u_mean", "order_u_inf", "order_u_l2", "order_p_mean",
                                   "seconds_per_step"});
  auto config = std::make_shared<std::string>();
  add_config_option(cmd, *config);
  cmd->callback([a, cmd, config] {
    if (!config->empty()) {
      apply_problem_file(*cmd, *config);
      reject_output_over_input(*cmd);
    }
    a->frame_given = cmd->count("--frame") > 0;
    a->shifting_given = cmd->count("--shifting") > 0;
    run_flow(*a);
  });
}

}  // namespace vrsph::cli
