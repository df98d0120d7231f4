// SPDX-License-Identifier: BSD-3-Clause
// The flow layer (vrsph::FlowSolver and the Taylor–Green study) for Python: the solver steps a
// velocity given as an (N, dim) array; the study returns its row as a dict.
#include <vrsph/core/error.hpp>
#include <vrsph/flow/cavity.hpp>
#include <vrsph/flow/dam_break.hpp>
#include <vrsph/flow/tank.hpp>
#include <vrsph/flow/flow_study.hpp>
#include <vrsph/kernels/kernel.hpp>
#include "bindings.hpp"
#include "cloud_cache.hpp"

namespace vrsph::python {

namespace {

Eigen::MatrixXd matrix_from(const py::handle& values, Index n, int dim, const char* what) {
  const auto a = py::array_t<Real, py::array::c_style | py::array::forcecast>::ensure(values);
  check<InputError>(a && a.ndim() == 2 && a.shape(0) == n && a.shape(1) == dim, what, " must be an (N, dim) = (", n, ", ",
                    dim, ") array of numbers");
  Eigen::MatrixXd m(n, dim);
  const Real* p = a.data();
  for (Index i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) m(i, k) = p[i * dim + k];
  return m;
}

py::array_t<Real> array_of(const Eigen::MatrixXd& m) {
  py::array_t<Real> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index k = 0; k < m.cols(); ++k) w(i, k) = m(i, k);
  return out;
}

FlowOptions flow_options(const std::string& frame, const std::string& method, const std::string& gradient, double nu,
                         const std::string& scheme, double h_factor, const std::string& kernel, const py::dict& options,
                         const std::string& shifting, double shift_coefficient, bool allow_unstable,
                         const std::string& viscosity) {
  FlowOptions o;
  o.frame = parse_flow_frame(frame);
  o.scheme = parse_flow_scheme(scheme);
  o.viscosity = parse_flow_viscosity(viscosity);
  o.operators.method = method;
  o.operators.method_options = method_options_from(options);
  o.operators.h_factor = h_factor;
  o.operators.kernel = parse_kernel(kernel);
  o.gradient = gradient;
  o.nu = nu;
  o.shifting = {parse_shifting(shifting), shift_coefficient};
  o.allow_unstable = allow_unstable;
  return o;
}

py::dict report_dict(const FlowStepReport& r) {
  py::dict d;
  d["step"] = r.step;
  d["t"] = r.t;
  d["dt"] = r.dt;
  d["kinetic_energy"] = r.kinetic_energy;
  d["max_speed"] = r.max_speed;
  d["max_div_u"] = r.max_div_u;
  d["cfl"] = r.cfl;
  d["advective_number"] = r.advective_number;
  d["viscous_number"] = r.viscous_number;
  d["ppe_iterations"] = r.ppe_iterations;
  d["ppe_setups"] = r.ppe_setups;
  d["min_spacing"] = r.min_spacing;
  d["max_spacing"] = r.max_spacing;
  d["min_support_isotropy"] = r.min_support_isotropy;
  d["max_support_growth"] = r.max_support_growth;
  d["max_shift"] = r.max_shift;
  d["wall_pushes"] = r.wall_pushes;
  d["seconds_update"] = r.seconds_update;
  d["seconds_ppe"] = r.seconds_ppe;
  d["seconds_rhs"] = r.seconds_rhs;
  d["seconds_viscous"] = r.seconds_viscous;
  d["viscous_iterations"] = r.viscous_iterations;
  d["warnings"] = r.warnings;
  return d;
}

std::unique_ptr<FlowSolver> make_solver(const py::object& cloud, const py::handle& velocity, const std::string& frame,
                                        const std::string& method, const std::string& gradient, double nu,
                                        const std::string& scheme, double h_factor, const std::string& kernel,
                                        const py::dict& options, const std::string& shifting, double shift_coefficient,
                                        bool allow_unstable, const py::object& wall_velocity, const py::object& body_force,
                                        bool free_surface, double body_force_ramp, const std::string& viscosity,
                                        double support_growth, double support_isotropy, std::optional<bool> warm_start,
                                        const std::string& wall_acceleration, const std::string& surface_gradient,
                                        double wall_gap, double shift_limit, std::optional<int> pressure_corrections,
                                        double surface_film) {
  const PointCloud& c = as_cloud(cloud);
  const Eigen::MatrixXd u0 = matrix_from(velocity, c.size(), c.dim, "velocity");
  FlowOptions o = flow_options(frame, method, gradient, nu, scheme, h_factor, kernel, options, shifting, shift_coefficient,
                               allow_unstable, viscosity);
  if (!body_force.is_none()) {
    const Eigen::MatrixXd g = matrix_from(body_force, 1, c.dim, "body_force");
    o.body_force.head(c.dim) = g.row(0).transpose();
  }
  o.free_surface = free_surface;
  o.body_force_ramp = body_force_ramp;
  o.support_growth = support_growth;
  o.support_isotropy_target = support_isotropy;
  o.warm_start = warm_start;
  o.wall_acceleration = parse_wall_acceleration(wall_acceleration);
  o.surface_gradient = parse_surface_gradient(surface_gradient);
  o.surface.film_eigenvalue = surface_film;
  o.wall_gap = wall_gap;
  o.shifting.max_shift = shift_limit;
  o.pressure_corrections = pressure_corrections;
  if (!wall_velocity.is_none()) {
    // An (N, dim) array: the rows of the wall particles are their velocities (the rest unused).
    auto walls = std::make_shared<Eigen::MatrixXd>(matrix_from(wall_velocity, c.size(), c.dim, "wall_velocity"));
    o.wall_velocity = [walls](Index i, const Vec3&) {
      Vec3 v = Vec3::Zero();
      v.head(walls->cols()) = walls->row(i).transpose();
      return v;
    };
  }
  py::gil_scoped_release release;
  return std::make_unique<FlowSolver>(c, u0, std::move(o));
}

py::dict cavity(int nx, double re, const std::string& method, const std::string& gradient, double jitter,
                std::uint64_t seed, double t_end, double steady_tolerance, double cfl, double h_factor,
                const py::dict& options, const std::string& viscosity, const std::string& frame,
                const std::string& shifting, int wall_layers, std::optional<int> pressure_corrections) {
  CavityRunOptions o;
  o.cloud = {nx, jitter, seed, wall_layers};
  o.re = re;
  o.t_end = t_end;
  o.steady_tolerance = steady_tolerance;
  o.cfl = cfl;
  o.flow = flow_options(frame, method, gradient, 0, "rk3", h_factor, "cubic", options, shifting, 0, false, viscosity);
  o.flow.pressure_corrections = pressure_corrections;
  CavityRunRow r;
  {
    py::gil_scoped_release release;
    r = run_cavity(o);
  }
  py::dict d;
  d["nx"] = r.nx;
  d["particles"] = r.particles;
  d["re"] = r.re;
  d["pressure_corrections"] = pressure_corrections_for(o.flow);
  d["t"] = r.t;
  d["steps"] = r.steps;
  d["dt"] = r.dt;
  d["steady"] = r.steady;
  d["steady_residual"] = r.steady_residual;
  d["average_time"] = r.average_time;
  d["profile_fluctuation"] = r.profile_fluctuation;
  d["wall_pushes"] = r.wall_pushes;
  d["ghia_max_deviation_u"] = r.ghia_max_deviation_u;
  d["ghia_max_deviation_v"] = r.ghia_max_deviation_v;
  d["reference_max_deviation_u"] = r.reference_max_deviation_u;
  d["reference_max_deviation_v"] = r.reference_max_deviation_v;
  d["u_at_ghia"] = r.u_at_ghia;
  d["v_at_ghia"] = r.v_at_ghia;
  d["max_div_u"] = r.max_div_u;
  d["seconds_per_step"] = r.seconds_per_step;
  d["line"] = r.line;
  d["u_line"] = r.u_line;
  d["v_line"] = r.v_line;
  return d;
}

py::dict taylor_green(int nx, int dim, const std::string& frame, const std::string& method, const std::string& gradient,
                      double t_end, double re, double cfl, double jitter, std::uint64_t seed, const std::string& scheme,
                      double h_factor, const py::dict& options, const std::string& shifting, double shift_coefficient,
                      const std::string& viscosity, double support_growth, double support_isotropy,
                      std::optional<bool> warm_start, std::optional<int> pressure_corrections) {
  VortexRunOptions o;
  o.cloud = {dim, nx, jitter, seed};
  o.vortex.Re = re;
  o.t_end = t_end;
  o.cfl = cfl;
  o.flow = flow_options(frame, method, gradient, 0, scheme, h_factor, "cubic", options, shifting, shift_coefficient, false,
                        viscosity);
  o.flow.support_growth = support_growth;
  o.flow.support_isotropy_target = support_isotropy;
  o.flow.warm_start = warm_start;
  o.flow.pressure_corrections = pressure_corrections;
  VortexRunRow r;
  {
    py::gil_scoped_release release;
    r = run_periodic_vortex(o);
  }
  py::dict d;
  d["nx"] = r.nx;
  d["particles"] = r.particles;
  d["pressure_corrections"] = pressure_corrections_for(o.flow);
  d["t"] = r.t;
  d["steps"] = r.steps;
  d["dt"] = r.dt;
  d["error_u_mean"] = r.errors.error_u_mean;
  d["error_u_inf"] = r.errors.error_u_inf;
  d["error_p_mean"] = r.errors.error_p_mean;
  d["error_p_inf"] = r.errors.error_p_inf;
  d["decay_rate_error"] = r.errors.decay_rate_error;
  d["max_div_u"] = r.max_div_u;
  d["kinetic_energy"] = r.kinetic_energy;
  d["min_spacing"] = r.min_spacing;
  d["max_spacing"] = r.max_spacing;
  d["min_support_isotropy"] = r.min_support_isotropy;
  d["max_support_growth"] = r.max_support_growth;
  d["volumes"] = r.warm_start ? "warm" : "cold";
  d["support_growth"] = r.support_growth;
  d["seconds_per_step"] = r.seconds_per_step;
  return d;
}

}  // namespace

void bind_flow(py::module_& m) {
  py::class_<FlowSolver>(m, "_FlowSolver")
      .def(py::init(&make_solver), py::arg("cloud"), py::arg("velocity"), py::arg("frame"), py::arg("method"),
           py::arg("gradient"), py::arg("nu"), py::arg("scheme"), py::arg("h_factor"), py::arg("kernel"), py::arg("options"),
           py::arg("shifting"), py::arg("shift_coefficient"), py::arg("allow_unstable"), py::arg("wall_velocity"),
           py::arg("body_force"), py::arg("free_surface"), py::arg("body_force_ramp"), py::arg("viscosity"),
           py::arg("support_growth"), py::arg("support_isotropy"), py::arg("warm_start") = py::none(),
           py::arg("wall_acceleration") = "momentum", py::arg("surface_gradient") = "linear", py::arg("wall_gap") = 0.0,
           py::arg("shift_limit") = 0.25, py::arg("pressure_corrections") = py::none(), py::arg("surface_film") = 0.1)
      .def("step", [](FlowSolver& s, double dt) {
        FlowStepReport r;
        {
          py::gil_scoped_release release;
          r = s.step(dt);
        }
        return report_dict(r);
      }, py::arg("dt"))
      .def("stable_time_step", &FlowSolver::stable_time_step, py::arg("safety"))
      .def("pressure", [](const FlowSolver& s) {
        const Field p = s.pressure();
        return py::array_t<Real>(static_cast<py::ssize_t>(p.size()), p.data());
      })
      .def_property_readonly("velocity", [](const FlowSolver& s) { return array_of(s.velocity()); })
      .def_property_readonly("positions", [](const FlowSolver& s) { return positions_array(s.operators().cloud()); })
      .def_property_readonly("time", &FlowSolver::time)
      .def_property_readonly("steps", &FlowSolver::steps)
      .def_property_readonly("max_divergence", &FlowSolver::max_divergence)
      .def_property_readonly("free_surface", [](const FlowSolver& s) {
        const auto& f = s.surface().surface;
        py::array_t<bool> out(static_cast<py::ssize_t>(f.size()));
        auto v = out.mutable_unchecked<1>();
        for (std::size_t i = 0; i < f.size(); ++i) v(static_cast<py::ssize_t>(i)) = f[i] != 0;
        return out;
      });
  m.def("_hydrostatic", [](int nx, int dim, const std::string& frame, const std::string& method, double jitter,
                           std::uint64_t seed, double t_end, double gravity, double ramp, double h_factor,
                           const py::dict& options, const std::string& surface_gradient, double wall_height,
                           double surface_film) {
    HydrostaticRunOptions o;
    o.tank.dim = dim;
    o.tank.nx = nx;
    o.tank.jitter = jitter;
    o.tank.seed = seed;
    o.tank.wall_height = wall_height;  // 0: up to the water's level
    o.t_end = t_end;
    o.gravity = gravity;
    o.ramp = ramp;
    o.flow = flow_options(frame, method, "auto", 0.01, "rk3", h_factor, "cubic", options, "none", 0, false, "explicit");
    o.flow.surface_gradient = parse_surface_gradient(surface_gradient);
    o.flow.surface.film_eigenvalue = surface_film;
    HydrostaticRow r;
    {
      py::gil_scoped_release release;
      r = run_hydrostatic(o);
    }
    py::dict d;
    d["nx"] = r.nx;
    d["particles"] = r.particles;
    d["water_particles"] = r.water_particles;
    d["t"] = r.t;
    d["steps"] = r.steps;
    d["dt"] = r.dt;
    d["bottom_pressure"] = r.bottom_pressure;
    d["bottom_pressure_error"] = r.bottom_pressure_error;
    d["pressure_profile_error"] = r.pressure_profile_error;
    d["max_speed"] = r.max_speed;
    d["max_speed_after_ramp"] = r.max_speed_after_ramp;
    d["surface_particles"] = r.surface_particles;
    d["surface_rise"] = r.surface_rise;
    d["surface_drop"] = r.surface_drop;
    d["max_div_u"] = r.max_div_u;
    d["seconds_per_step"] = r.seconds_per_step;
    d["line_y"] = r.line_y;
    d["line_p"] = r.line_p;
    return d;
  }, py::arg("nx"), py::arg("dim"), py::arg("frame"), py::arg("method"), py::arg("jitter"), py::arg("seed"),
     py::arg("t_end"), py::arg("gravity"), py::arg("ramp"), py::arg("h_factor"), py::arg("options"),
     py::arg("surface_gradient"), py::arg("wall_height"), py::arg("surface_film") = 0.1);
  m.def("_dam_break", [](int nx, const std::string& method, double jitter, std::uint64_t seed, double t_star_end,
                         const std::string& shifting, double cfl, double h_factor, const py::dict& options,
                         const std::string& geometry, const std::string& wall_acceleration,
                         const std::string& surface_gradient, double surface_film) {
    DamBreakRunOptions o;
    o.geometry = parse_dam_break_geometry(geometry);
    o.nx = nx;
    o.jitter = jitter;
    o.seed = seed;
    o.t_star_end = t_star_end;
    o.cfl = cfl;
    o.flow = flow_options("lagrangian", method, "auto", 0.01, "rk3", h_factor, "cubic", options, shifting, 0, false, "explicit");
    o.flow.wall_acceleration = parse_wall_acceleration(wall_acceleration);
    o.flow.surface_gradient = parse_surface_gradient(surface_gradient);
    o.flow.surface.film_eigenvalue = surface_film;
    DamBreakRun r;
    {
      py::gil_scoped_release release;
      r = run_dam_break(o);
    }
    py::dict d;
    std::vector<Real> t, z, h, h_exp, lo, hi, mps, probe, probe_ref;
    for (const DamBreakSample& s : r.samples) {
      probe.push_back(s.probe_pressure);
      probe_ref.push_back(s.probe_reference);
      t.push_back(s.t_star);
      z.push_back(s.front_z_over_l);
      h.push_back(s.column_height_over_l);
      h_exp.push_back(s.experiment_height);
      lo.push_back(s.experiment_low);
      hi.push_back(s.experiment_high);
      mps.push_back(s.mps);
    }
    d["nx"] = r.nx;
    d["particles"] = r.particles;
    d["steps"] = r.steps;
    d["t_star"] = t;
    d["front_z_over_l"] = z;
    d["column_height_over_l"] = h;
    d["experiment_height_over_l"] = h_exp;
    d["experiment_low"] = lo;
    d["experiment_high"] = hi;
    d["mps_z_over_l"] = mps;
    d["max_outside_experiments"] = r.max_outside_experiments;
    d["max_height_deviation"] = r.max_height_deviation;
    d["reached_far_wall"] = r.reached_far_wall;
    d["far_wall_t_star"] = r.far_wall_t_star;
    d["probe_pressure"] = probe;
    d["probe_reference"] = probe_ref;
    d["probe_peak"] = r.probe_peak;
    d["probe_plateau"] = r.probe_plateau;
    d["stopped"] = r.stopped;
    d["seconds_per_step"] = r.seconds_per_step;
    return d;
  }, py::arg("nx"), py::arg("method"), py::arg("jitter"), py::arg("seed"), py::arg("t_star_end"), py::arg("shifting"),
     py::arg("cfl"), py::arg("h_factor"), py::arg("options"), py::arg("geometry"), py::arg("wall_acceleration"),
     py::arg("surface_gradient"), py::arg("surface_film") = 0.1);
  m.def("_cavity", &cavity, py::arg("nx"), py::arg("re"), py::arg("method"), py::arg("gradient"), py::arg("jitter"),
        py::arg("seed"), py::arg("t_end"), py::arg("steady_tolerance"), py::arg("cfl"), py::arg("h_factor"),
        py::arg("options"), py::arg("viscosity"), py::arg("frame"), py::arg("shifting"), py::arg("wall_layers"),
        py::arg("pressure_corrections") = py::none());
  m.def("_taylor_green", &taylor_green, py::arg("nx"), py::arg("dim"), py::arg("frame"), py::arg("method"), py::arg("gradient"),
        py::arg("t_end"), py::arg("re"), py::arg("cfl"), py::arg("jitter"), py::arg("seed"), py::arg("scheme"),
        py::arg("h_factor"), py::arg("options"), py::arg("shifting"), py::arg("shift_coefficient"), py::arg("viscosity"),
        py::arg("support_growth"), py::arg("support_isotropy"), py::arg("warm_start") = py::none(),
        py::arg("pressure_corrections") = py::none());
}

}  // namespace vrsph::python
