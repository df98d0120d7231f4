// SPDX-License-Identifier: BSD-3-Clause
// `vrsph flow --case hydrostatic`: water at rest in a tank under gravity, with a free surface
// (flow/tank.hpp): one row per method and --nx, the bottom pressure against g H, the pressure
// along the vertical, the spurious velocities and the surface's stability. `--case dam-break`:
// a column released in a tank (flow/dam_break.hpp), one row per sample of its surge front.
#include <cmath>
#include <iostream>
#include <memory>
#include <vrsph/io/json.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/tank.hpp>
#include "../vtu_series.hpp"
#include "flow_args.hpp"

namespace vrsph::cli {

namespace {
// The solver's free-surface flags as a VTU field (0/1).
PointField surface_field(const FlowSolver& s) {
  const std::vector<std::uint8_t>& flags = s.surface().surface;
  Eigen::MatrixXd values(static_cast<Index>(flags.size()), 1);
  for (std::size_t i = 0; i < flags.size(); ++i) values(static_cast<Index>(i), 0) = flags[i];
  return {"free_surface", values};
}

// One frame of a free-surface run: velocity, pressure, the surface flags, the supports' isotropy.
void write_frame(VtuSeries& series, const FlowSolver& s) {
  series.write(s.time(), s.operators().cloud(),
               {{"velocity", s.velocity()}, {"pressure", Eigen::MatrixXd(s.pressure())}, surface_field(s), isotropy_field(s)});
}
// The surface particles' gradient rows as the table says it: "linear" (their fit lowered to
// linear order, FlowOptions::surface_gradient) or "same" (the gradient's own rows there too).
std::string surface_gradient_of(FlowOptions flow) {
  flow.free_surface = true;  // as the case's run sets it
  return flow_operators(flow).marked_gradient_method.empty() ? "same" : "linear";
}
}  // namespace

const std::vector<std::string> hydrostatic_columns = {
    "case", "method", "gradient", "surface_gradient", "pressure_corrections", "frame", "dim", "nx", "particles", "water_particles", "t", "steps", "dt",
    "bottom_pressure", "bottom_pressure_error", "order_bottom_pressure", "pressure_profile_error", "max_speed",
    "max_speed_after_ramp", "surface_particles", "surface_rise", "surface_drop", "max_div_u", "ppe_iterations_per_step",
    "seconds_setup", "seconds_per_step", "seconds_update", "seconds_ppe", "seconds_rhs", "seconds_viscous", "status"};

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
  check<ConfigError>(std::isfinite(a.wall_height) && a.wall_height >= 0, "--wall-height must be positive (0: the "
                     "water's depth), got ", a.wall_height);
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
  FlowHistory history(a.history);
  for (const std::string& m : methods) {
    const std::size_t first = t.rows.size();
    std::map<std::string, std::vector<Real>> errors{{"order_bottom_pressure", {}}};
    for (const int n : nxs) {
      HydrostaticRunOptions o;
      o.tank.dim = a.dim;
      o.tank.nx = n;
      o.tank.width = width;
      o.tank.depth = depth;
      o.tank.wall_height = a.wall_height;  // 0: up to the water (run_hydrostatic)
      o.tank.jitter = a.cloud == "lattice" ? 0.0 : a.jitter;
      o.tank.seed = a.seed;
      if (a.wall_layers > 0) o.tank.wall_layers = a.wall_layers;
      o.gravity = a.gravity;
      o.ramp = ramp;
      o.t_end = t_end;
      o.dt = a.dt;
      o.flow = flow_options_for(a, m, options);
      o.flow.nu = scale * depth / a.re;
      std::unique_ptr<VtuSeries> series = series_for(a, methods, nxs, m, n);
      const double index = static_cast<double>(done++);
      o.on_step = [&](const FlowSolver& s) {
        progress.update(detail::concat(m, " nx = ", n, " t = ", s.time(), " max |u| = ", s.last().max_speed),
                        (index + s.time() / t_end) / runs);
        history.record("hydrostatic", m, n, s);
        const bool last = s.time() >= t_end * (1 - 1e-12);
        if (series && (last || (a.vtu_every > 0 && s.steps() % a.vtu_every == 0))) write_frame(*series, s);
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
                 {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method},
                 {"surface_gradient", surface_gradient_of(o.flow)},
                 {"pressure_corrections", static_cast<long long>(pressure_corrections_for(o.flow))}, {"frame", a.frame},
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
                 {"seconds_ppe", r.seconds_ppe}, {"seconds_rhs", r.seconds_rhs}, {"seconds_viscous", r.seconds_viscous}, {"status", std::string("ok")}});
    }
    add_orders(t, first, nxs, errors);
  }
  Json extra;
  extra["case"] = "hydrostatic";
  extra["exact_pressure"] = "g (H - y), unit density";
  extra["gravity"] = a.gravity;
  extra["depth"] = depth;
  extra["tank_width"] = width;
  extra["wall_height"] = a.wall_height > 0 ? a.wall_height : depth;
  extra["ramp"] = ramp;
  extra["t_end"] = t_end;
  extra["re"] = a.re;
  extra["speeds_in_units_of"] = "(g H)^(1/2)";
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  extra["peak_memory_mib"] = peak_memory_mib();
  history.write();
  emit(t, a.out, extra, "nx", "bottom_pressure_error:-1/-2,max_speed_after_ramp", "method",
       "hydrostatic tank: bottom pressure error and spurious speed");
  failed.raise_if_any();
}

const std::vector<std::string> dam_break_columns = {
    "case", "method", "gradient", "surface_gradient", "pressure_corrections", "shifting", "nx", "particles", "t", "t_star", "front_z_over_l", "column_height_over_l",
    "experiment_low", "experiment_high", "outside_experiments", "mps_z_over_l", "experiment_height_over_l", "max_speed",
    "surface_particles", "min_spacing", "probe_pressure", "probe_reference", "max_outside_experiments",
    "max_height_deviation", "reached_far_wall",
    "far_wall_t_star", "probe_peak", "probe_peak_t_star", "reference_peak", "reference_peak_t_star", "probe_plateau",
    "reference_plateau", "steps", "seconds_per_step", "seconds_ppe", "status"};

void run_dam_break_case(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                        const std::map<std::string, MethodOptions>& options) {
  check<ConfigError>(a.dim == 2, "the dam break is two-dimensional (--dim 2), got --dim ", a.dim);
  check<ConfigError>(a.frame == "lagrangian", "the dam break's water moves: --frame lagrangian, got --frame ", a.frame);
  check<ConfigError>(a.cloud == "perturbed" || a.cloud == "lattice", "--cloud for flow is perturbed or lattice, got ",
                     a.cloud);
  check<ConfigError>(std::isfinite(a.cfl) && a.cfl > 0 && a.cfl <= 1, "--cfl for the dam break must be in (0, 1], got ",
                     a.cfl);
  check<ConfigError>(a.re > 0 && std::isfinite(a.re), "--re must be positive, got ", a.re);  // as the hydrostatic tank's
  // L = g = 1: T = t √2. Default: T = 3.54 (t = 2.5), beyond the experiments' z/L = 3.5.
  const DamBreakGeometry geometry = parse_dam_break_geometry(a.geometry);
  const bool buchner = geometry == DamBreakGeometry::Buchner;
  const Real t_end = a.t_end > 0 ? a.t_end : buchner ? 8.0 : 2.5;  // Buchner: past the wave's return to the wall
  Table t;
  t.columns = dam_break_columns;
  Progress progress;
  std::size_t done = 0;
  const double runs = static_cast<double>(methods.size() * nxs.size());
  FailedRuns failed;
  FlowHistory history(a.history);
  for (const std::string& m : methods) {
    for (const int n : nxs) {
      check<ConfigError>(n <= 400, "--nx for the dam break counts intervals across the column (the tank is 4 times "
                         "wider): at most 400, got ", n);
      DamBreakRunOptions o;
      o.nx = n;
      o.jitter = a.cloud == "lattice" ? 0.0 : a.jitter;
      o.seed = a.seed;
      if (a.wall_layers > 0) o.wall_layers = a.wall_layers;
      o.geometry = geometry;
      o.t_star_end = buchner ? t_end : t_end * std::sqrt(2.0);
      o.cfl = a.cfl;
      o.flow = flow_options_for(a, m, options);
      if (a.wall_gap) o.wall_gap = *a.wall_gap;  // 0 given: none
      o.flow.nu = buchner ? 1 / a.re : std::sqrt(2.0) / a.re;  // Re = (g 2L)^½ L / ν; Buchner: (g H)^½ H / ν
      std::unique_ptr<VtuSeries> series = series_for(a, methods, nxs, m, n);
      const double index = static_cast<double>(done++);
      o.on_step = [&](const FlowSolver& s) {
        progress.update(detail::concat(m, " nx = ", n, " t = ", s.time()), (index + s.time() / t_end) / runs);
        history.record("dam-break", m, n, s);
        // The end too, as the other cases (the solver's time ends at --t-end in either geometry's units).
        const bool last = s.time() >= t_end * (1 - 1e-12);
        if (series && (last || (a.vtu_every > 0 && s.steps() % a.vtu_every == 0))) write_frame(*series, s);
      };
      DamBreakRun r;
      if (!failed.attempt(t, {{"case", std::string("dam-break")}, {"method", m}, {"nx", static_cast<long long>(n)}},
                          [&] { r = run_dam_break(o); }))
        continue;
      const OperatorsOptions ops = flow_operators(o.flow);
      for (std::size_t k = 0; k < r.samples.size(); ++k) {
        const DamBreakSample& s = r.samples[k];
        const auto number = [](Real v) { return std::isfinite(v) ? TableCell(v) : TableCell(); };
        std::vector<std::pair<std::string, TableCell>> row = {
            {"case", std::string("dam-break")}, {"method", m},
            {"gradient", ops.gradient_method.empty() ? m : ops.gradient_method},
            {"surface_gradient", surface_gradient_of(o.flow)},
            {"pressure_corrections", static_cast<long long>(pressure_corrections_for(o.flow))}, {"shifting", a.shifting},
            {"nx", static_cast<long long>(n)}, {"particles", static_cast<long long>(r.particles)},
            {"t", buchner ? s.t_star : s.t_star / std::sqrt(2.0)}, {"t_star", s.t_star}, {"front_z_over_l", s.front_z_over_l},
            {"column_height_over_l", s.column_height_over_l}, {"experiment_low", number(s.experiment_low)},
            {"experiment_high", number(s.experiment_high)}, {"outside_experiments", number(s.outside_experiments)},
            {"mps_z_over_l", number(s.mps)}, {"experiment_height_over_l", number(s.experiment_height)},
            {"max_speed", s.max_speed},
            {"surface_particles", static_cast<long long>(s.surface_particles)}, {"min_spacing", s.min_spacing},
            {"probe_pressure", number(s.probe_pressure)}, {"probe_reference", number(s.probe_reference)},
            {"status", std::string(k + 1 == r.samples.size() && !r.stopped.empty() ? r.stopped : "ok")}};
        if (k + 1 == r.samples.size()) {  // the run's summary on its last row
          row.emplace_back("max_outside_experiments", number(r.max_outside_experiments));
          row.emplace_back("max_height_deviation", number(r.max_height_deviation));
          row.emplace_back("reached_far_wall", r.reached_far_wall);
          row.emplace_back("far_wall_t_star", r.reached_far_wall ? TableCell(r.far_wall_t_star) : TableCell());
          for (const auto& [name, v] : {std::pair{"probe_peak", r.probe_peak}, {"probe_peak_t_star", r.probe_peak_t_star},
                                        {"reference_peak", r.reference_peak}, {"reference_peak_t_star", r.reference_peak_t_star},
                                        {"probe_plateau", r.probe_plateau}, {"reference_plateau", r.reference_plateau}})
            row.emplace_back(name, number(v));
          row.emplace_back("steps", static_cast<long long>(r.steps));
          row.emplace_back("seconds_per_step", r.seconds_per_step);
          row.emplace_back("seconds_ppe", r.seconds_ppe);
        }
        t.add_row(row);
      }
      if (!r.stopped.empty()) failed.messages.push_back(r.stopped);  // its samples kept, the command fails
    }
  }
  Json extra;
  extra["case"] = "dam-break";
  Json curves = Json::array();
  if (buchner) {
    extra["geometry"] = "buchner: column 2H x H, tank 5.366H wide, walls 6H, H = g = 1, T = t (g / H)^(1/2), probe P1 on "
                        "the far wall at 0.2667 H, p / (rho g H)";
    extra["references"] = Json::array({"Buchner, Green water on ship-type offshore structures, PhD thesis, TU Delft (2002), "
                                       "probe P1 (digitised in TrixiParticles.jl's validation)"});
    const SurgeCurve& c = buchner_probe_reference();
    curves.push_back(Json::object({{"name", c.name}, {"t_star", c.t_star}, {"probe_pressure", c.z_over_l}}));
  } else {
    extra["geometry"] = "martin-moyce: column L x 2L, tank 4L wide, L = g = 1, T = t (2 g / L)^(1/2)";
    extra["references"] = Json::array({"Martin & Moyce, Phil. Trans. R. Soc. A 244 (1952) 312-324, Fig. 3 (n^2 = 2, a = 1.125 in and 2.25 in) and Table 6 (the column height, n^2 = 2)",
                           "Koshizuka & Oka, Nucl. Sci. Eng. 123 (1996) 421-434 (MPS)"});
    for (const SurgeCurve& c : dam_break_references())
      curves.push_back(Json::object({{"name", c.name}, {"t_star", c.t_star}, {"z_over_l", c.z_over_l}}));
    const SurgeCurve& h = martin_moyce_height_reference();
    extra["height_reference"] = Json::object({{"name", h.name}, {"t_star", h.t_star}, {"height_over_l", h.z_over_l}});
  }
  extra["reference_curves"] = curves;
  extra["t_end"] = t_end;
  extra["cfl"] = a.cfl;
  extra["re"] = a.re;
  extra["jitter"] = a.cloud == "lattice" ? 0.0 : a.jitter;
  extra["h_factor"] = a.h_factor;
  extra["seed"] = a.seed;
  extra["peak_memory_mib"] = peak_memory_mib();
  history.write();
  OutputOptions table_only = a.out;
  table_only.plot.clear();  // the front against T beside the references: a plot of its own
  emit(t, table_only, extra, "", "", "", "");
  if (!a.out.plot.empty() && communicator().rank() == 0) {
    const TemporaryFile data("vrsph-dam-break", ".json");
    write_file(data.path(), "temporary plot data", [&](std::ostream& f) { f << to_json(t, extra); });
    run_plot_script("plot_dam_break.py", data.path(), a.out.plot);
  }
  failed.raise_if_any();
}

}  // namespace vrsph::cli
