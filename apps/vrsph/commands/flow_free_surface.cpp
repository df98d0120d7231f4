// SPDX-License-Identifier: BSD-3-Clause
// `vrsph flow --case hydrostatic`: water at rest in a tank under gravity, with a free surface
// (flow/tank.hpp): one row per method and --nx, the bottom pressure against g H, the pressure
// along the vertical, the spurious velocities and the surface's stability.
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <vrsph/flow/tank.hpp>
#include "../vtu_series.hpp"
#include "flow_args.hpp"

namespace vrsph::cli {

const std::vector<std::string> hydrostatic_columns = {
    "case", "method", "gradient", "frame", "dim", "nx", "particles", "water_particles", "t", "steps", "dt",
    "bottom_pressure", "bottom_pressure_error", "order_bottom_pressure", "pressure_profile_error", "max_speed",
    "max_speed_after_ramp", "surface_particles", "surface_rise", "surface_drop", "max_div_u", "ppe_iterations_per_step",
    "seconds_setup", "seconds_per_step", "seconds_update", "seconds_ppe", "seconds_rhs", "status"};

void run_hydrostatic_case(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                          const std::map<std::string, MethodOptions>& options) {
  check<ConfigError>(a.cloud == "perturbed" || a.cloud == "lattice", "--cloud for flow is perturbed or lattice, got ",
                     a.cloud);
  check<ConfigError>(std::isfinite(a.gravity) && a.gravity > 0, "--gravity must be positive (a free surface with no "
                     "gravity has nothing to hold it), got ", a.gravity);
  check<ConfigError>(a.re > 0 && std::isfinite(a.re), "--re must be positive, got ", a.re);
  const Real width = a.tank_width > 0 ? a.tank_width : 1.0;
  const Real depth = a.depth > 0 ? a.depth : width;
  check<ConfigError>(a.depth >= 0 && a.tank_width >= 0 && std::isfinite(a.depth) && std::isfinite(a.tank_width),
                     "--depth and --tank-width must be positive");
  const Real scale = std::sqrt(a.gravity * depth);  // (g H)^½, the velocity scale
  const Real ramp = a.ramp >= 0 ? a.ramp : 0.5 * depth / scale;
  check<ConfigError>(std::isfinite(ramp), "--ramp must be finite and >= 0, got ", a.ramp);
  const Real t_end = a.t_end > 0 ? a.t_end : 2 * depth / scale;
  Table t;
  t.columns = hydrostatic_columns;
  Progress progress;
  std::size_t done = 0;
  const double runs = static_cast<double>(methods.size() * nxs.size());
  FailedRuns failed;
  for (const std::string& m : methods) {
    const std::size_t first = t.rows.size();
    std::map<std::string, std::vector<Real>> errors{{"order_bottom_pressure", {}}};
    for (const int n : nxs) {
      HydrostaticRunOptions o;
      o.tank.dim = a.dim;
      o.tank.nx = n;
      o.tank.width = width;
      o.tank.depth = depth;
      o.tank.jitter = a.cloud == "lattice" ? 0.0 : a.jitter;
      o.tank.seed = a.seed;
      o.gravity = a.gravity;
      o.ramp = ramp;
      o.t_end = t_end;
      o.dt = a.dt;
      o.flow = flow_options_for(a, m, options);
      o.flow.nu = scale * depth / a.re;
      std::unique_ptr<VtuSeries> series;
      if (!a.vtu_series.empty() && m == methods.front() && n == nxs.back()) series = std::make_unique<VtuSeries>(a.vtu_series);
      const double index = static_cast<double>(done++);
      o.on_step = [&](const FlowSolver& s) {
        progress.update(detail::concat(m, " nx = ", n, " t = ", s.time(), " max |u| = ", s.last().max_speed),
                        (index + s.time() / t_end) / runs);
        const bool last = s.time() >= t_end * (1 - 1e-12);
        if (series && (last || (a.vtu_every > 0 && s.steps() % a.vtu_every == 0))) {
          const std::vector<std::uint8_t>& flags = s.surface().surface;
          Eigen::MatrixXd surface(static_cast<Index>(flags.size()), 1);
          for (std::size_t i = 0; i < flags.size(); ++i) surface(static_cast<Index>(i), 0) = flags[i];
          series->write(s.time(), s.operators().cloud(),
                        {{"velocity", s.velocity()}, {"pressure", Eigen::MatrixXd(s.pressure())}, {"free_surface", surface}});
        }
      };
      HydrostaticRow r;
      if (!failed.attempt(t, {{"case", std::string("hydrostatic")}, {"method", m}, {"nx", static_cast<long long>(n)}},
                          [&] { r = run_hydrostatic(o); })) {
        skip_orders(errors);
        continue;
      }
      errors["order_bottom_pressure"].push_back(r.bottom_pressure_error);
      const OperatorsOptions ops = flow_operators(o.flow);
      t.add_row({{"case", std::string("hydrostatic")}, {"method", m},
                 {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method}, {"frame", a.frame},
                 {"dim", static_cast<long long>(a.dim)}, {"nx", static_cast<long long>(n)},
                 {"particles", static_cast<long long>(r.particles)},
                 {"water_particles", static_cast<long long>(r.water_particles)}, {"t", r.t},
                 {"steps", static_cast<long long>(r.steps)}, {"dt", r.dt}, {"bottom_pressure", r.bottom_pressure},
                 {"bottom_pressure_error", r.bottom_pressure_error}, {"pressure_profile_error", r.pressure_profile_error},
                 {"max_speed", r.max_speed}, {"max_speed_after_ramp", r.max_speed_after_ramp},
                 {"surface_particles", static_cast<long long>(r.surface_particles)}, {"surface_rise", r.surface_rise},
                 {"surface_drop", r.surface_drop}, {"max_div_u", r.max_div_u},
                 {"ppe_iterations_per_step", r.ppe_iterations_per_step}, {"seconds_setup", r.seconds_setup},
                 {"seconds_per_step", r.seconds_per_step}, {"seconds_update", r.seconds_update},
                 {"seconds_ppe", r.seconds_ppe}, {"seconds_rhs", r.seconds_rhs}, {"status", std::string("ok")}});
    }
    add_orders(t, first, nxs, errors);
  }
  nlohmann::ordered_json extra;
  extra["case"] = "hydrostatic";
  extra["exact_pressure"] = "g (H - y), unit density";
  extra["gravity"] = a.gravity;
  extra["depth"] = depth;
  extra["tank_width"] = width;
  extra["ramp"] = ramp;
  extra["t_end"] = t_end;
  extra["re"] = a.re;
  extra["speeds_in_units_of"] = "(g H)^(1/2)";
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  extra["peak_memory_mib"] = peak_memory_mib();
  emit(t, a.out, extra.dump(), "nx", "bottom_pressure_error:-1/-2,max_speed_after_ramp", "method",
       "hydrostatic tank: bottom pressure error and spurious speed");
  failed.raise_if_any();
}

}  // namespace vrsph::cli
