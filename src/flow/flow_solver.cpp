// SPDX-License-Identifier: BSD-3-Clause
// The projection-per-stage Runge–Kutta flow solver (flow_solver.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <vrsph/analysis/support_isotropy.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/flow/flow_solver.hpp>
#include <vrsph/flow/projection.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/stencil/properties.hpp>

namespace vrsph {

FlowFrame parse_flow_frame(const std::string& name) {
  if (name == "eulerian") return FlowFrame::Eulerian;
  if (name == "lagrangian") return FlowFrame::Lagrangian;
  throw ConfigError(detail::concat("unknown frame '", name, "' (known: eulerian, lagrangian)"));
}

FlowScheme parse_flow_scheme(const std::string& name) {
  if (name == "rk2") return FlowScheme::RK2;
  if (name == "rk3") return FlowScheme::RK3;
  throw ConfigError(detail::concat("unknown time scheme '", name, "' (known: rk2, rk3)"));
}

FlowViscosity parse_flow_viscosity(const std::string& name) {
  if (name == "explicit") return FlowViscosity::Explicit;
  if (name == "implicit") return FlowViscosity::Implicit;
  throw ConfigError(detail::concat("unknown viscous treatment '", name, "' (known: explicit, implicit)"));
}

WallAcceleration parse_wall_acceleration(const std::string& name) {
  if (name == "momentum") return WallAcceleration::Momentum;
  if (name == "body-force") return WallAcceleration::BodyForce;
  throw ConfigError(detail::concat("unknown wall acceleration '", name, "' (known: momentum, body-force)"));
}

SurfaceGradient parse_surface_gradient(const std::string& name) {
  if (name == "linear") return SurfaceGradient::Linear;
  if (name == "same") return SurfaceGradient::Same;
  throw ConfigError(detail::concat("unknown surface gradient '", name, "' (known: linear, same)"));
}

std::string to_string(FlowFrame f) { return f == FlowFrame::Eulerian ? "eulerian" : "lagrangian"; }
std::string to_string(FlowScheme s) { return s == FlowScheme::RK2 ? "rk2" : "rk3"; }
std::string to_string(FlowViscosity v) { return v == FlowViscosity::Explicit ? "explicit" : "implicit"; }
std::string to_string(WallAcceleration a) { return a == WallAcceleration::Momentum ? "momentum" : "body-force"; }
std::string to_string(SurfaceGradient g) { return g == SurfaceGradient::Linear ? "linear" : "same"; }

namespace {

// max_i Σ_j |L_ij| over the fluid rows: a bound of the spectral radius (Gershgorin).
Real row_sum_bound(const Stencil& s, const Walls& walls) {
  Real b = 0;
  for (Index i = 0; i < s.rows(); ++i) {
    if (!walls.empty() && walls.is_wall[static_cast<std::size_t>(i)]) continue;
    Real r = 0;
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) r += std::abs(s.values[0][static_cast<std::size_t>(k)]);
    b = std::max(b, r);
  }
  return b;
}

// ρ(L) over the fluid rows (the walls' velocities are data), what the explicit viscous term's
// step is limited by. Eulerian: the operators are built once, so it is measured (power
// iteration, with 2 % for its estimate from below); the Gershgorin bound max Σ|L_ij| is about
// twice ρ on perturbed clouds and halved the step of every viscous-limited run. Lagrangian: the
// operators change at every stage, and the bound (one pass over the rows) stays.
Real laplacian_radius(const Stencil& L, const Walls& walls, FlowFrame frame) {
  if (frame == FlowFrame::Lagrangian) return row_sum_bound(L, walls);
  std::vector<char> fluid(static_cast<std::size_t>(L.rows()), 1);
  if (!walls.empty())
    for (std::size_t i = 0; i < fluid.size(); ++i) fluid[i] = walls.is_wall[i] ? 0 : 1;
  return 1.02 * spectral_radius(L, fluid);
}

// The same error with "flow step k (t = ...): " in front, of the same type.
[[noreturn]] void rethrow_at(const Error& e, Index step, Real t) {
  const std::string m = detail::concat("flow step ", step, " (t = ", t, "): ", e.what());
  if (dynamic_cast<const ResourceError*>(&e)) throw ResourceError(m);
  if (dynamic_cast<const ConfigError*>(&e)) throw ConfigError(m);
  if (dynamic_cast<const GeometryError*>(&e)) throw GeometryError(m);
  if (dynamic_cast<const NumericalError*>(&e)) throw NumericalError(m);
  // Within a step the only positions checked are the ones the flow moved its particles to:
  // coinciding or non-finite ones are the run's failure (particles piled up), not bad input.
  if (dynamic_cast<const InputError*>(&e)) throw GeometryError(m);
  throw;
}

// The first fluid particle outside the box along a bounded axis, or -1: a particle that crossed a
// wall or was flung out of its tank.
Index first_outside(const PointCloud& cloud, const Walls& walls) {
  const Domain& box = cloud.domain;
  for (Index i = 0; i < cloud.size(); ++i) {
    if (!walls.empty() && walls.is_wall[static_cast<std::size_t>(i)]) continue;
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int a = 0; a < cloud.dim; ++a)
      if (!box.periodic[static_cast<std::size_t>(a)] && (x[a] < box.lo[a] || x[a] > box.hi[a])) return i;
  }
  return -1;
}

Real max_row_norm(const Eigen::MatrixXd& u) { return u.rows() ? u.rowwise().norm().maxCoeff() : 0.0; }

// One pressure solve in the step's report (iterations, the largest shift λ, seconds).
void count_solve(FlowStepReport& r, const SolveReport& solve, Real shift, double seconds) {
  r.ppe_iterations += solve.iterations;
  r.ppe_shift = std::max(r.ppe_shift, std::abs(shift));
  r.seconds_ppe += seconds;
}

}  // namespace

int pressure_corrections_for(const FlowOptions& options) {
  // Automatic: VRSPH's Laplacian only. With FPM's own Laplacian the first correction raises
  // |D(a - G p)| (Taylor-Green nx = 32: 90 -> 102) and the pressure error (9.0e-3 -> 2.5e-2 at t =
  // 1, the velocity's unchanged); the classic SPH and MPS keep their published scheme.
  if (options.pressure_corrections) return *options.pressure_corrections;
  return options.operators.method == "vrsph" ? 1 : 0;
}

OperatorsOptions flow_operators(const FlowOptions& options) {
  OperatorsOptions o = options.operators;
  o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient};
  o.use = StencilUse::Values;
  // A free surface breaks up: a droplet that leaves the water's reach has empty rows, the air's
  // p = 0 (it is a surface particle) and falls freely, instead of stopping the run.
  if (options.free_surface) o.min_neighbours = 0;
  if (options.gradient == "own") {
    o.gradient_method.clear();
  } else if (options.gradient == "auto") {
    if (o.method == "vrsph") {
      // VRSPH's NNLS gradient rows pick a few neighbours each; composed into D G they have
      // modes of the wrong sign against L, and the projection amplifies them (ρ(P) = 1.22 at
      // jitter 0.2): docs/flow.md. A least-squares gradient has none. prefer=near keeps the
      // Laplacian's rows on an exact lattice from splitting into two checkerboards.
      o.gradient_method = "fpm";
      if (!o.gradient_method_options.values().contains("gradient_order")) o.gradient_method_options.set("gradient_order", "2");
      if (!o.method_options.values().contains("prefer") && !o.method_options.values().contains("profile"))
        o.method_options.set("prefer", "near");
    } else {
      o.gradient_method.clear();
      // FPM and KGF as published: their linear fit. Their default cubic rows (for operators)
      // made the flow blow up with their own Laplacian (Taylor-Green nx = 32 at t = 0.07, where
      // the linear rows converge at third order: docs/flow.md).
      if ((o.method == "fpm" || o.method == "kgf") && !o.method_options.values().contains("gradient_order") &&
          !o.method_options.values().contains("profile"))
        o.method_options.set("gradient_order", "1");
    }
  } else {
    (void)builtin_methods().info(options.gradient);  // ConfigError listing the methods (besides auto and own)
    o.gradient_method = options.gradient;
  }
  // The surface rows' linear fit (SurfaceGradient): the gradient's own method, one order lower.
  // The flow marks the rows itself (the surface's, after each detection): a marked method given
  // in options.operators is not used.
  o.marked_gradient_method.clear();
  o.marked_gradient_method_options = {};
  const bool fit = o.gradient_method == "fpm" || o.gradient_method == "kgf";
  const auto& given = o.gradient_method_options.values();
  const bool above_linear = !given.contains("gradient_order") || given.at("gradient_order") != "1";
  if (options.free_surface && options.surface_gradient == SurfaceGradient::Linear && fit && above_linear) {
    o.marked_gradient_method = o.gradient_method;
    o.marked_gradient_method_options = o.gradient_method_options;  // its options, one order lower
    o.marked_gradient_method_options.set("gradient_order", "1");
  }
  return o;
}

FlowSolver::FlowSolver(PointCloud cloud, const Eigen::MatrixXd& u0, FlowOptions options) : options_(std::move(options)) {
  validate(cloud);
  const int d = cloud.dim;
  check<ConfigError>(d >= 2, "flow: the dimension must be 2 or 3, got ", d);
  check<ConfigError>(cloud.domain.shape == Domain::Shape::Box, "flow: the domain must be a box (periodic axes and walls)");
  eq_.walls = walls_of(cloud);
  check<ConfigError>(!eq_.walls.empty() || cloud.domain.fully_periodic(), "flow: a box that is not periodic along every "
                     "axis needs wall particles (tag dirichlet, with outward normals) on its other faces");
  check<InputError>(u0.rows() == cloud.size() && u0.cols() == d, "flow: an initial velocity of ", u0.rows(), " x ",
                    u0.cols(), " for ", cloud.size(), " particles in ", d, "D");
  check<InputError>(u0.allFinite(), "flow: the initial velocity is not finite");
  Eigen::MatrixXd start = u0;
  Real wall_speed = 0;
  for (std::size_t w = 0; w < eq_.walls.index.size(); ++w) {
    const Index i = eq_.walls.index[w];
    const Vec3 x = cloud.positions[static_cast<std::size_t>(i)];
    const Vec3 v = options_.wall_velocity ? options_.wall_velocity(i, x) : Vec3::Zero();
    check<InputError>(v.allFinite(), "flow: the wall velocity at particle ", i, " is not finite");
    for (int c = d; c < 3; ++c)
      check<InputError>(v[c] == 0, "flow: a wall velocity along axis ", c, " of a ", d, "D flow (particle ", i, ")");
    check<InputError>(std::abs(v.dot(eq_.walls.normal[w])) <= 1e-12 * (1 + v.norm()), "flow: wall particle ", i,
                      " moves through the wall (u·n = ", v.dot(eq_.walls.normal[w]), "); walls may only slide along "
                      "themselves");
    start.row(i) = v.head(d).transpose();
    wall_speed = std::max(wall_speed, v.norm());
  }
  check<ConfigError>(std::isfinite(options_.nu) && options_.nu >= 0, "flow: the viscosity must be finite and >= 0, got ",
                     options_.nu);
  check<ConfigError>(std::isfinite(options_.wall_gap) && options_.wall_gap >= 0 && options_.wall_gap < 1,
                     "flow: the wall gap must be in [0, 1) particle spacings, got ", options_.wall_gap);
  for (const Index i : eq_.walls.index)  // the faces the wall gap keeps particles off: those with walls on them
    for (int a = 0; a < d; ++a) {
      const auto k = static_cast<std::size_t>(a);
      const Real x = cloud.positions[static_cast<std::size_t>(i)][a], tol = 1e-9 * cloud.spacing;
      if (cloud.domain.periodic[k]) continue;
      if (std::abs(x - cloud.domain.lo[a]) <= tol) wall_faces_[k][0] = true;
      if (std::abs(x - cloud.domain.hi[a]) <= tol) wall_faces_[k][1] = true;
    }
  check<ConfigError>(options_.body_force.allFinite(), "flow: the body force must be finite");
  for (int c = d; c < 3; ++c)
    check<ConfigError>(options_.body_force[c] == 0, "flow: a body force along axis ", c, " of a ", d, "D flow");
  options_.operators = flow_operators(options_);
  if (options_.free_surface) {
    // Above the water the walls' particles stand in a line, and a splash's droplets hold a few
    // particles: their least-squares rows are singular. They are left zero (no pressure gradient
    // acts on a lone droplet; a dry wall's rows are not used). Nearly singular rows count too: a
    // 3D wall particle above the water sees the wall's plane and the water's flat top row, whose
    // quadratic fit is singular until the water moves by 1e-7 dx; its condition then falls from
    // 1e18 through the methods' default limit of 1e12, and the row's weights of ~1e6 threw the
    // water out of the tank within a step (docs/free_surface.md). Healthy rows, one-sided ones at
    // a box's corners included, stay below 2e3 (FPM, perturbed boxes, 2D and 3D): 1e6 is the limit.
    // The same for every least-squares fit the flow builds: the Laplacian's method, the
    // gradient's and the surface rows' (SurfaceGradient; empty name: none).
    OperatorsOptions& ops = options_.operators;
    const std::string& gradient = ops.gradient_method.empty() ? ops.method : ops.gradient_method;
    const std::pair<MethodOptions*, const std::string*> fits[] = {{&ops.method_options, &ops.method},
                                                                  {&ops.gradient_method_options, &gradient},
                                                                  {&ops.marked_gradient_method_options, &ops.marked_gradient_method}};
    for (const auto& [m, name] : fits) {
      if (name->empty()) continue;
      const MethodInfo& info = builtin_methods().info(*name);
      const auto declares = [&info](const char* key) {
        return std::any_of(info.options.begin(), info.options.end(), [key](const auto& kv) { return kv.first == key; });
      };
      if (declares("on_singular") && !m->values().contains("on_singular")) m->set("on_singular", "warn");
      if (declares("max_condition") && !m->values().contains("max_condition"))
        m->set("max_condition", detail::concat(free_surface_max_condition));
    }
  }
  check<ConfigError>(options_.shifting.kind == Shifting::None || options_.frame == FlowFrame::Lagrangian,
                     "flow: particle shifting moves particles; it applies to the lagrangian frame only");
  check<ConfigError>(std::isfinite(options_.shifting.coefficient) && options_.shifting.coefficient >= 0,
                     "flow: the shifting coefficient must be finite and >= 0, got ", options_.shifting.coefficient);
  check<ConfigError>(std::isfinite(options_.shifting.max_shift) && options_.shifting.max_shift >= 0,
                     "flow: the largest shift must be finite and >= 0 spacings (0: unbounded), got ",
                     options_.shifting.max_shift);
  options_.solver.dimension = d;
  // Every pressure set-up serves several solves: the stages of a fixed cloud, or the nearby
  // matrices of the next stages (reuse_hierarchy): the solver's defaults favour iterations.
  options_.solver.reused_setup = options_.frame == FlowFrame::Eulerian || options_.reuse_hierarchy;
  // The Lagrangian frame sets up a new pressure matrix at every stage, where auto's direct limit
  // was measured for one set-up per solve: Taylor-Green, per step, UMFPACK against GMRES +
  // BoomerAMG 2D 0.0089 / 0.011 s at 625 particles, 0.022 / 0.018 at 1089, 0.74 / 0.22 at
  // 16 641; 3D 0.106 (UMFPACK preconditioning the next stages) / 0.026 at 1331 (docs/flow.md).
  if (options_.frame == FlowFrame::Lagrangian && options_.solver.type == SolverType::Auto &&
      options_.solver.auto_direct_max == 0 && built_with("PETSC"))
    options_.solver.auto_direct_max = lagrangian_direct_limit(d);
  check<ConfigError>(std::isfinite(options_.support_growth) && (options_.support_growth >= 1 || options_.support_growth == 0),
                     "flow: support_growth must be finite and >= 1 (1: fixed supports; 0: automatic), got ",
                     options_.support_growth);
  check<ConfigError>(options_.support_growth <= 1 || options_.frame == FlowFrame::Lagrangian,
                     "flow: growing supports follow moving particles; they apply to the lagrangian frame only");
  check<ConfigError>(options_.support_isotropy_target > 0 && options_.support_isotropy_target <= 0.5,
                     "flow: the support isotropy target must be in (0, 0.5], got ", options_.support_isotropy_target);
  if (options_.warm_start) options_.operators.warm_start = *options_.warm_start;
  else if (stretches_freely(cloud)) options_.operators.warm_start = false;
  options_.warm_start = options_.operators.warm_start;
  // Checked before the operators are built: a bad value costs no build.
  options_.pressure_corrections = pressure_corrections_for(options_);
  check<ConfigError>(*options_.pressure_corrections >= 0 && *options_.pressure_corrections <= 10,
                     "flow: pressure_corrections must be in [0, 10], got ", *options_.pressure_corrections);
  ops_ = std::make_unique<Operators>(std::move(cloud), options_.operators);
  spacing_ = ops_->spacing();
  if (options_.support_growth == 0) options_.support_growth = automatic_support_growth();
  if (options_.support_growth > 1 && ops_->cloud().domain.any_periodic()) {
    const Domain& box = ops_->cloud().domain;
    const Real largest = options_.support_growth * ops_->radius() + options_.operators.skin * ops_->radius();
    for (int k = 0; k < d; ++k)
      check<ConfigError>(!box.periodic[static_cast<std::size_t>(k)] || largest < 0.499 * box.period(k),
                         "flow: support_growth ", options_.support_growth, " lets a support radius reach ",
                         options_.support_growth * ops_->radius(), " (with the Verlet skin ", largest,
                         "), not below half the period ", box.period(k), " of axis ", k, ": lower it or refine the cloud");
  }
  laplacian_bound_ = laplacian_radius(ops_->stencil(OperatorKind::Laplacian), eq_.walls, options_.frame);
  check<ConfigError>(std::isfinite(options_.max_speed_growth) && options_.max_speed_growth >= 0,
                     "flow: max_speed_growth must be finite and >= 0, got ", options_.max_speed_growth);
  check<ConfigError>(std::isfinite(options_.hyperviscosity) && options_.hyperviscosity >= 0 &&
                     std::isfinite(options_.velocity_scale) && options_.velocity_scale >= 0,
                     "flow: the hyperviscosity coefficient and the velocity scale must be finite and >= 0");
  check<ConfigError>(std::isfinite(options_.body_force_ramp) && options_.body_force_ramp >= 0,
                     "flow: the body-force ramp time must be finite and >= 0, got ", options_.body_force_ramp);
  if (options_.free_surface) {
    check<ConfigError>(!options_.body_force.isZero() || !start.isZero(), "flow: a free surface with neither a body force "
                       "nor an initial velocity: nothing drives this flow (give it a body force: gravity)");
    options_.surface.only_interior = true;
    options_.surface.spacing = spacing_;
    detect_surface();
  }
  if (options_.frame == FlowFrame::Eulerian) {
    const Real U = options_.velocity_scale > 0 ? options_.velocity_scale : max_row_norm(start);
    gamma_ = options_.hyperviscosity * U * spacing_ * spacing_ * spacing_;
  }
  try {
    factorise_pressure();
  } catch (const NumericalError& e) {
    explain_pressure_failure(e);
  }
  FlowStepReport r;
  u_ = project_state(start, r);
  report_ = r;
  finish_report(report_);
  // Without a body force nothing feeds a periodic flow: its kinetic energy can only fall (the
  // viscous dissipation), so a step that raises it by 5 % is an instability, not a result.
  // A local instability (a few particles) hardly moves the energy: their speed is bounded too.
  // Moving walls feed the flow: its energy may grow, but no particle of a stable run outruns
  // the fastest wall by much (a lid-driven cavity's fluid stays below the lid's speed).
  if (options_.body_force.isZero()) {
    if (wall_speed == 0) energy_bound_ = 1.05 * report_.kinetic_energy;
    if (options_.max_speed_growth > 0)
      speed_bound_ = options_.max_speed_growth * std::max(report_.max_speed, wall_speed);
  } else if (options_.max_speed_growth > 0) {
    // Gravity in a closed box (no periodic axis along it): no particle falls faster than
    // freely across the whole box, √(2 |g| D). The pressure's jets outrun free fall (a dam
    // break's front runs at about 2 (g H)^½), hence twice that; a blow-up passes it within a
    // few steps, where it would otherwise shorten the steps towards zero (a dam break in the
    // tank of Buchner's experiment did, at t = 1.54, its pressure doubling every step).
    const Domain& box = ops_->cloud().domain;
    const Vec3 g = options_.body_force;
    bool closed = box.shape == Domain::Shape::Box;
    Real drop = 0;
    for (int k = 0; k < ops_->cloud().dim && closed; ++k) {
      if (g[k] == 0) continue;
      closed = !box.periodic[static_cast<std::size_t>(k)];
      drop += std::abs(g[k]) / g.norm() * box.period(k);
    }
    if (closed && drop > 0)
      speed_bound_ = options_.max_speed_growth *
                     (std::max(report_.max_speed, wall_speed) + 2 * std::sqrt(2 * g.norm() * drop));
  }
}

bool FlowSolver::factorise_pressure() {
  // A free surface: p = 0 there, and the walls' rows carry the water's pressure to them
  // (extrapolated rows: exact for the hydrostatic pressure on either side of the surface, and
  // they hold up the water at a column's foot, where a wall's balance row over a quarter support
  // could not; docs/free_surface.md). Walls in the Lagrangian frame take them too: with balance
  // rows the fluid particle next to a lid's corner was flung off within 25 steps (the cavity,
  // docs/flow.md), with these the water keeps off the walls by itself.
  const bool extrapolated = options_.free_surface || (options_.frame == FlowFrame::Lagrangian && !eq_.walls.empty());
  PressureEquation eq =
      extrapolated ? extrapolated_pressure_equation(
                         *ops_, eq_.walls,
                         options_.free_surface ? std::vector<char>(surface_.surface.begin(), surface_.surface.end())
                                               : std::vector<char>())
                   : pressure_equation(*ops_, eq_.walls);
  eq_.wall_flux = std::move(eq.wall_flux);
  eq_.surface = std::move(eq.surface);
  eq_.wall_offset = std::move(eq.wall_offset);
  const bool reuse = ppe_ && (ppe_->hierarchy() ? options_.reuse_hierarchy : options_.reuse_factorisation);
  const PressurePoisson* previous = reuse && ppe_->worth_reusing() ? ppe_.get() : nullptr;
  ppe_ = std::make_unique<PressurePoisson>(pressure_poisson(std::move(eq.matrix), eq_.walls, eq_.wall_flux,
                                                            options_.solver, eq_.has_surface(), previous,
                                                            !eq_.wall_offset.empty()));
  return previous != nullptr;
}

// A support too small for the method's moment conditions leaves its Laplacian rows infeasible
// throughout the fluid, and the pressure matrix can then be singular: the solver's "factorisation
// failed" is said with that cause. (Rows that are infeasible and still make a solvable matrix are
// left alone, as a boundary value problem's are: a dam break's lattice column at h = 1.45 dx gives
// VRSPH rows from the four nearest neighbours, none of them feasible, and runs. A few infeasible
// rows are normal under a free surface; most of the fluid's are not.)
void FlowSolver::explain_pressure_failure(const NumericalError& failure) const {
  const Stencil& L = ops_->stencil(OperatorKind::Laplacian);
  const Index n = ops_->cloud().size();
  std::vector<char> rows(static_cast<std::size_t>(n), 1);
  Index fluid = n;
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const bool wall = !eq_.walls.empty() && eq_.walls.is_wall[si];
    const bool surface = options_.free_surface && si < surface_.surface.size() && surface_.surface[si];
    if (wall || surface) {
      rows[si] = 0;
      --fluid;
    }
  }
  const LocalResidualSummary bad = summarise_local_residuals(L, rows, 1e-6, 1);
  if (fluid == 0 || 2 * bad.infeasible <= fluid) throw failure;
  const Index worst = bad.worst.front().second;
  throw ConfigError(detail::concat(
      "flow: the pressure equation could not be solved (", failure.what(), "): the support radius ", ops_->radius(), " (",
      options_.operators.h_factor, " particle spacings) is too small for ", options_.operators.method,
      "'s Laplacian, whose rows cannot meet their moment conditions at ", bad.infeasible, " of ", fluid,
      " fluid particles (particle ", worst, " has ", ops_->neighbours().count(worst), " neighbours); use a larger h-factor"));
}

void FlowSolver::detect_surface() {
  surface_ = detect_free_surface(ops_->cloud(), options_.surface);
  if (!options_.operators.marked_gradient_method.empty())  // the surface's gradient rows (SurfaceGradient)
    ops_->set_marked_rows(open_surface_rows());
  check<GeometryError>(surface_.count > 0 || ops_->cloud().domain.fully_periodic(), "flow: no free-surface particle was "
                       "found (a free surface needs fluid particles with an open side)");
}

// The surface particles whose supports only the air cuts: no wall particle among their neighbours.
// Beside a wall, the wall's layers of particles (carrying the water's extrapolated pressure) fill
// that side of the support, and the quadratic rows held there: measured (docs/free_surface.md),
// linear rows beside the walls too left the tank at rest as still, but made a dam break's surge
// front, which runs along the floor, 0.02-0.03 L faster.
std::vector<char> FlowSolver::open_surface_rows() const {
  std::vector<char> open(surface_.surface.begin(), surface_.surface.end());
  if (eq_.walls.empty()) return open;
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (!open[i]) continue;
    for (const Index j : ops_->neighbours().of(static_cast<Index>(i)))
      if (eq_.walls.is_wall[static_cast<std::size_t>(j)]) {
        open[i] = 0;
        break;
      }
  }
  return open;
}

Vec3 FlowSolver::body_force(Real t) const {
  const Real T = options_.body_force_ramp;
  if (T <= 0 || t >= T) return options_.body_force;
  return options_.body_force * (0.5 * (1 - std::cos(std::numbers::pi * t / T)));
}

Real FlowSolver::force_limit() const {
  const Real g = options_.body_force.norm();
  if (!options_.free_surface || g == 0) return std::numeric_limits<Real>::infinity();
  return 0.25 * std::sqrt(spacing_ / g);
}

FlowSolver::~FlowSolver() = default;
FlowSolver::FlowSolver(FlowSolver&&) noexcept = default;
FlowSolver& FlowSolver::operator=(FlowSolver&&) noexcept = default;

const ImexTableau& FlowSolver::imex_tableau() const {
  return options_.scheme == FlowScheme::RK3 ? ars443() : ars222();
}

FlowSolver::Limits FlowSolver::limits() const {
  // Stability intervals of the schemes' polynomials: RK3 reaches √3 along the imaginary axis and
  // 2.51 along the negative real one; RK2 (Heun) 2 along the real axis and, strictly, nothing
  // along the imaginary one (|1 + z + z²/2| = (1 + y⁴/4)^½): its advective limit of 1 relies
  // on the viscosity to damp that growth. The IMEX schemes' explicit parts: implicit_viscosity.cpp.
  if (options_.viscosity == FlowViscosity::Implicit) {
    const ImexTableau& t = imex_tableau();
    return Limits{t.imaginary_limit, t.real_limit};
  }
  return options_.scheme == FlowScheme::RK3 ? Limits{std::sqrt(3.0), 2.51} : Limits{1.0, 2.0};
}

Real FlowSolver::advective_bound(const Eigen::MatrixXd& u) const {
  if (options_.frame == FlowFrame::Lagrangian) return max_row_norm(u) / spacing_;  // the CFL number's rate
  const Stencil& G = ops_->stencil(OperatorKind::Gradient);
  const int d = G.dim;
  Real b = 0;
  for (Index i = 0; i < G.rows(); ++i) {
    if (!eq_.walls.empty() && eq_.walls.is_wall[static_cast<std::size_t>(i)]) continue;  // walls do not advance
    Real r = 0;
    for (Index k = G.row_begin(i); k < G.row_end(i); ++k) {
      Real a = 0;
      for (int c = 0; c < d; ++c) a += u(i, c) * G.values[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)];
      r += std::abs(a);
    }
    b = std::max(b, r);
  }
  return b;
}

Real FlowSolver::viscous_rate() const {
  // ν ρ(L) + γ ρ(L)²: the bounds of the viscous and the hyperviscous terms' spectral radii (the
  // hyperviscosity is explicit in either treatment).
  const Real hyper = gamma_ * laplacian_bound_ * laplacian_bound_;
  return options_.viscosity == FlowViscosity::Implicit ? hyper : options_.nu * laplacian_bound_ + hyper;
}

Real FlowSolver::stable_time_step(Real safety) const {
  check<ConfigError>(std::isfinite(safety) && safety > 0 && safety <= 1, "flow: the safety factor must be in (0, 1]");
  const Limits lim = limits();
  const Real rate = advective_bound(u_) / lim.advective + viscous_rate() / lim.viscous + 1 / force_limit();
  return rate > 0 ? safety / rate : std::numeric_limits<Real>::infinity();
}

Eigen::MatrixXd FlowSolver::forces(const Eigen::MatrixXd& u, Real t) const {
  return forces(u, t, ops_->apply(VectorOperator::VectorLaplacian, u));
}

Eigen::MatrixXd FlowSolver::forces(const Eigen::MatrixXd& u, Real t, Eigen::MatrixXd lap) const {
  wall_laplacian(u, lap);
  Eigen::MatrixXd f = options_.nu * lap;
  if (gamma_ > 0) f -= gamma_ * ops_->apply(VectorOperator::VectorLaplacian, lap);
  const Vec3 g = body_force(t);
  for (int c = 0; c < u.cols(); ++c)
    if (g[c] != 0) f.col(c).array() += g[c];
  return f;
}

void FlowSolver::wall_laplacian(const Eigen::MatrixXd& u, Eigen::MatrixXd& lap) const {
  if (eq_.walls.empty()) return;
  // A wall particle's Laplacian row sees a half (a quarter at a corner) of its support: Σ_a ∂_a ∂_a
  // from the least-squares gradient of the gradient reads the fluid's rows instead.
  const Stencil& G = ops_->stencil(OperatorKind::Gradient);
  const int d = G.dim;
  for (int c = 0; c < d; ++c) {
    const Eigen::MatrixXd g = ops_->apply(OperatorKind::Gradient, Field(u.col(c)));  // ∂_a u_c
    for (const Index i : eq_.walls.index) {
      Real s = 0;
      for (Index k = G.row_begin(i); k < G.row_end(i); ++k) {
        const Index j = G.col[static_cast<std::size_t>(k)];
        for (int a = 0; a < d; ++a) s += G.values[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)] * g(j, a);
      }
      lap(i, c) = s;
    }
  }
}

Field FlowSolver::pressure_of(const Eigen::MatrixXd& f, const Eigen::MatrixXd& adv, Real t, FlowStepReport* r,
                              const Eigen::MatrixXd* implicit) const {
  const Stopwatch watch;
  // ∂u/∂t = f - (u·∇)u - ∇p stays divergence-free: L p = D (f - (u·G)u); at walls, which do not
  // accelerate, n·G p = n·(f - (u·G)u).
  Eigen::MatrixXd a = f - adv;
  if (options_.free_surface && options_.wall_acceleration == WallAcceleration::BodyForce && !eq_.wall_offset.empty()) {
    // Extrapolated wall rows that carry the body force only, as Adami, Hu & Adams's for walls at
    // rest: p_w = Σ ω (p_f + g·(x_w - x_f)). The wall's ν∇²u, from the gradient applied twice
    // over half a support, is the under-resolved shear of the water sliding past it; carried
    // along the offsets it made the wall's pressure fall along a jet running up the far wall of
    // a dam break and pumped the jet out of the tank (docs/free_surface.md).
    const Vec3 g = body_force(t);
    for (const Index i : eq_.walls.index)
      for (int c = 0; c < a.cols(); ++c) a(i, c) = g[c];
  }
  Field p = phi_;
  const PressurePoisson::Result res = ppe_->solve(pressure_rhs(*ops_, eq_, a), p);
  const int corrections = *options_.pressure_corrections;  // set by the constructor
  if (corrections > 0 && implicit) a += *implicit;  // the rate whose divergence they remove (a is not needed after)
  for (int c = 0; c < corrections; ++c) {
    Field delta = Field::Zero(p.size());
    const PressurePoisson::Result more = ppe_->solve(rate_divergence(a, p), delta);
    p += delta;
    if (r) count_solve(*r, more.report, more.shift, 0.0);
  }
  if (r) count_solve(*r, res.report, res.shift, watch.seconds());
  return p;
}

Field FlowSolver::rate_divergence(const Eigen::MatrixXd& a, const Field& p) const {
  Eigen::MatrixXd k = a - ops_->apply(OperatorKind::Gradient, p);
  for (const Index i : eq_.walls.index) k.row(i).setZero();
  Field div = ops_->apply(VectorOperator::Divergence, k).col(0);
  for (const Index i : eq_.walls.index) div[i] = 0;  // the wall rows' conditions hold already
  for (std::size_t i = 0; i < eq_.surface.size(); ++i)
    if (eq_.surface[i]) div[static_cast<Index>(i)] = 0;  // p = 0 there
  return div;
}

Eigen::MatrixXd FlowSolver::rate(const Eigen::MatrixXd& u, Real t, FlowStepReport& r) {
  Stopwatch watch;
  const Eigen::MatrixXd f = forces(u, t);
  const Eigen::MatrixXd adv = advection(*ops_, u);
  r.seconds_rhs += watch.seconds();
  phi_ = pressure_of(f, adv, t, &r);
  watch.restart();
  // Eulerian: ∂u/∂t = f - (u·∇)u - ∇p; Lagrangian: Du/Dt = f - ∇p (the particles carry the advection).
  Eigen::MatrixXd k = f - ops_->apply(OperatorKind::Gradient, phi_);
  if (options_.frame == FlowFrame::Eulerian) k -= adv;
  for (const Index i : eq_.walls.index) k.row(i).setZero();  // the walls' velocity is prescribed
  r.seconds_rhs += watch.seconds();
  return k;
}

std::pair<Eigen::MatrixXd, Eigen::MatrixXd> FlowSolver::imex_rates(const Eigen::MatrixXd& u, Real t,
                                                                    FlowStepReport& r) {
  Stopwatch watch;
  const Eigen::MatrixXd lap = ops_->apply(VectorOperator::VectorLaplacian, u);
  Eigen::MatrixXd f = forces(u, t, lap);
  Eigen::MatrixXd viscous = options_.nu * lap;
  for (const Index i : eq_.walls.index) viscous.row(i).setZero();
  const Eigen::MatrixXd adv = advection(*ops_, u);
  // The pressure balances the explicit part: ∇²p = ∇·(g - (u·∇)u) inside (∇·ν∇²u vanishes for a
  // divergence-free u, so the implicit term's divergence is left to the step's projection), and
  // the walls' n·∇p = n·(ν∇²u - (u·∇)u + g) keeps the viscous term (from f: Σ G G u there).
  // Measured against keeping D(ν L u) in the pressure (the explicit scheme's, whose steady states
  // it then shares at equal dt): the cavity's steady state moves less with dt (Re = 1, nx = 32,
  // kinetic energy +4 % instead of +25 % at dt = 1e-2 over dt -> 0; docs/flow.md).
  f -= viscous;
  r.seconds_rhs += watch.seconds();
  phi_ = pressure_of(f, adv, t, &r, &viscous);
  watch.restart();
  Eigen::MatrixXd k = f - ops_->apply(OperatorKind::Gradient, phi_);
  if (options_.frame == FlowFrame::Eulerian) k -= adv;
  for (const Index i : eq_.walls.index) k.row(i).setZero();
  r.seconds_rhs += watch.seconds();
  return {std::move(k), std::move(viscous)};
}

const ImplicitViscosity& FlowSolver::viscous_solver(Real c, FlowStepReport& r) {
  if (!viscous_ || viscous_->coefficient() != c) {
    const Stopwatch watch;
    viscous_.reset();
    viscous_ = std::make_unique<ImplicitViscosity>(*ops_, eq_.walls, c, options_.solver);
    r.seconds_viscous += watch.seconds();
  }
  return *viscous_;
}

Eigen::MatrixXd FlowSolver::imex_step(const Eigen::MatrixXd& un, Real dt, const StageMove& move, FlowStepReport& r) {
  const ImexTableau& T = imex_tableau();
  const bool lagrangian = options_.frame == FlowFrame::Lagrangian;
  const auto s = static_cast<std::size_t>(T.stages);
  std::vector<Eigen::MatrixXd> U(s), KE(s - 1), KI(s - 1);
  U[0] = un;
  std::tie(KE[0], KI[0]) = imex_rates(un, t_, r);  // KI[0] is not used: the tableaux start explicit
  for (std::size_t i = 1; i < s; ++i) {
    Eigen::MatrixXd R = un;
    for (std::size_t j = 0; j < i; ++j) {
      if (T.explicit_a[i][j] != 0) R += dt * T.explicit_a[i][j] * KE[j];
      if (j > 0 && T.implicit_a[i][j] != 0) R += dt * T.implicit_a[i][j] * KI[j];
    }
    if (lagrangian) {
      std::vector<std::pair<Real, const Eigen::MatrixXd*>> terms;
      for (std::size_t j = 0; j < i; ++j)
        if (T.explicit_a[i][j] != 0) terms.emplace_back(T.explicit_a[i][j], &U[j]);
      move(terms);
    }
    const Real c = dt * T.implicit_a[i][i] * options_.nu;
    if (c > 0) {
      const ImplicitViscosity& solver = viscous_solver(c, r);
      const Stopwatch watch;
      const int before = solver.iterations();
      U[i] = solver.solve(R, U[i - 1]);
      r.viscous_iterations += solver.iterations() - before;
      r.seconds_viscous += watch.seconds();
    } else {
      U[i] = std::move(R);
    }
    if (i + 1 < s) std::tie(KE[i], KI[i]) = imex_rates(U[i], t_ + T.c[i] * dt, r);
  }
  return std::move(U[s - 1]);
}

Eigen::MatrixXd FlowSolver::project_state(const Eigen::MatrixXd& w, FlowStepReport& r) {
  const Stopwatch watch;
  Projected p = project(*ops_, *ppe_, w, correction_, &eq_);
  correction_ = std::move(p.phi);
  count_solve(r, p.report, p.shift, watch.seconds());
  return std::move(p.u);
}

void FlowSolver::move_to(const std::vector<Vec3>& x, FlowStepReport& r) {
  Stopwatch watch;
  // The surface's rows are marked anew after the detection below: unmarked for the update, which
  // would otherwise build the old surface's rows only to replace them (kept if the update throws).
  std::vector<char> marks = ops_->marked_rows();
  if (!marks.empty()) ops_->set_marked_rows({});
  try {
    ops_->update(x);
  } catch (...) {
    if (!marks.empty()) ops_->set_marked_rows(std::move(marks));
    throw;
  }
  viscous_.reset();  // its matrix was the old positions'
  laplacian_bound_ = laplacian_radius(ops_->stencil(OperatorKind::Laplacian), eq_.walls, options_.frame);
  if (options_.free_surface) detect_surface();
  r.seconds_update += watch.seconds();
  watch.restart();
  r.ppe_setups += factorise_pressure() ? 0 : 1;
  r.ppe_iterations += ppe_->setup().iterations;
  r.seconds_ppe += watch.seconds();
}

void FlowSolver::shift(Eigen::MatrixXd& u, Real dt, FlowStepReport& r) {
  const Stopwatch watch;
  const Discretisation disc{ops_->cloud(), ops_->neighbours(), options_.operators.kernel, spacing_};
  std::vector<Vec3> dr = options_.shifting.kind == Shifting::None
                            ? std::vector<Vec3>(static_cast<std::size_t>(u.rows()), Vec3::Zero())
                            : shifting_displacements(disc, options_.shifting, u, dt);
  for (const Index i : eq_.walls.index) dr[static_cast<std::size_t>(i)].setZero();  // walls stay
  // A surface particle's support is cut: the shift would push it out of the fluid. It moves only
  // along the surface (Lind et al. 2012).
  for (std::size_t i = 0; i < surface_.surface.size(); ++i)
    if (surface_.surface[i]) dr[i] -= dr[i].dot(surface_.normals[i]) * surface_.normals[i];
  std::vector<Vec3> pushed(dr.size(), Vec3::Zero());  // each particle's reflection off a wall's gap
  if (options_.wall_gap > 0) {  // after the shift: no closer to a wall than the gap
    std::vector<Vec3> x(dr.size());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = ops_->cloud().positions[i] + dr[i];
    const std::vector<Vec3> back = wall_gap_displacements(x);
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!back[i].isZero()) {
        dr[i] += back[i];
        pushed[i] = back[i];
        ++r.wall_pushes;
      }
  }
  // Without shifting, a step that left every particle clear of the walls moves none: no update.
  if (std::all_of(dr.begin(), dr.end(), [](const Vec3& v) { return v.isZero(); })) return;
  // u at the shifted position: u + (∇u)·δr + ½ δrᵀ(∇∇u)δr with the flow's gradient, applied twice
  // for the Hessian. Xu et al.'s eq. (34) stops at the gradient; but the shifts are O(dt) each,
  // so that interpolation's O(δr²) error per step adds up to O(dt) — first order (measured: the
  // error grew from nx = 32 to 64 at t = 1). With the Hessian it is O(δr² dx) per step.
  const int d = static_cast<int>(u.cols());
  Eigen::MatrixXd du = Eigen::MatrixXd::Zero(u.rows(), d);
  for (int c = 0; c < d; ++c) {
    const Eigen::MatrixXd g = ops_->apply(OperatorKind::Gradient, Field(u.col(c)));
    for (Index i = 0; i < u.rows(); ++i) du(i, c) = g.row(i).dot(dr[static_cast<std::size_t>(i)].head(d));
    for (int b = 0; b < d; ++b) {
      const Eigen::MatrixXd h = ops_->apply(OperatorKind::Gradient, Field(g.col(b)));  // ∂_a ∂_b u_c
      for (Index i = 0; i < u.rows(); ++i) {
        const Vec3& s = dr[static_cast<std::size_t>(i)];
        du(i, c) += 0.5 * s[b] * h.row(i).dot(s.head(d));
      }
    }
  }
  // Surface particles keep their velocity: their gradient and Hessian rows see half a support,
  // so the expansion extrapolates, and at the tip of a jet (along the surface is along the jet,
  // outward) it fed the jet's stretching back into its speed step after step — a dam break's
  // run-up on the far wall went from 1.6 to 8.6 (g L)^½ in 20 steps and left the tank
  // (docs/free_surface.md). Their shifts are O(dt) and along the surface only.
  for (std::size_t i = 0; i < surface_.surface.size(); ++i)
    if (surface_.surface[i]) du.row(static_cast<Index>(i)).setZero();
  u += du;
  // A particle reflected off a wall's gap stops moving into that wall (an inelastic contact):
  // kept, its velocity took it back to the wall every step — a surface particle, which keeps
  // its velocity above, stayed pressed there, sliding along it.
  for (std::size_t i = 0; i < pushed.size(); ++i)
    for (int a = 0; a < d; ++a)
      if (pushed[i][a] * u(static_cast<Index>(i), a) < 0) u(static_cast<Index>(i), a) = 0;
  std::vector<Vec3> x = ops_->cloud().positions;
  const Domain& box = ops_->cloud().domain;
  for (std::size_t i = 0; i < x.size(); ++i) {
    r.max_shift = std::max(r.max_shift, dr[i].norm() / spacing_);
    x[i] = box.wrap(x[i] + dr[i]);
  }
  r.seconds_update += watch.seconds();
  move_to(x, r);
}

std::vector<Vec3> FlowSolver::wall_gap_displacements(const std::vector<Vec3>& x) const {
  std::vector<Vec3> dr(x.size(), Vec3::Zero());
  const Domain& box = ops_->cloud().domain;
  const Real gap = options_.wall_gap * spacing_;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!eq_.walls.empty() && eq_.walls.is_wall[i]) continue;
    for (int a = 0; a < ops_->cloud().dim; ++a) {
      const auto k = static_cast<std::size_t>(a);
      // Reflected off the plane at the gap, not set onto it: two particles pushed into a corner
      // landed on one point (Re = 1000 cavity, nx = 64), reflected ones stay apart.
      if (wall_faces_[k][0] && x[i][a] < box.lo[a] + gap) dr[i][a] = 2 * (box.lo[a] + gap - x[i][a]);
      if (wall_faces_[k][1] && x[i][a] > box.hi[a] - gap) dr[i][a] = 2 * (box.hi[a] - gap - x[i][a]);
    }
  }
  return dr;
}

Real FlowSolver::kinetic_energy(const Eigen::MatrixXd& u) const {
  // A free surface fills part of its box: each particle carries dx^d.
  const Real volume = options_.free_surface ? std::pow(spacing_, ops_->cloud().dim)
                                            : ops_->cloud().domain.measure() / static_cast<Real>(u.rows());
  return 0.5 * u.squaredNorm() * volume;
}

void FlowSolver::finish_report(FlowStepReport& r) const {
  r.t = t_;
  r.step = steps_;
  r.max_speed = max_row_norm(u_);
  r.kinetic_energy = kinetic_energy(u_);
  r.max_div_u = max_divergence();
  const NeighbourList& nl = ops_->neighbours();
  Real lo = std::numeric_limits<Real>::infinity(), hi = 0;
  for (Index i = 0; i < nl.size(); ++i) {
    const auto d = nl.distances_of(i);
    if (d.empty()) continue;
    const Real nearest = *std::min_element(d.begin(), d.end());
    lo = std::min(lo, nearest);
    hi = std::max(hi, nearest);
  }
  r.min_spacing = lo / spacing_;
  r.max_spacing = hi / spacing_;
  // A fixed (Eulerian) cloud keeps its supports and surface flags: measured once, at construction
  // (steps_ == 0), not rescanned at every step.
  r.min_support_isotropy = options_.frame == FlowFrame::Lagrangian || steps_ == 0 ? least_isotropic_support().first
                                                                                  : report_.min_support_isotropy;
  r.surface_particles = surface_.count;
  const std::vector<Real>& radii = ops_->support_radii();
  r.max_support_growth = *std::max_element(radii.begin(), radii.end()) / ops_->radius();
}

// Supports that follow the stretching, all together: every support grows by 15 % while the least
// isotropic fluid support is below the target, and shrinks by 5 % toward the base once it is above
// twice the target (the band between keeps the radius from flickering: growing lifts the isotropy
// it is measured with). Growing only the supports below the target was tried first: Taylor-Green,
// nx = 64, h = 3 dx, every support kept above 0.27 (and 0.41) — and the run blew up at t = 0.258,
// as with fixed 3 dx supports (0.242); grown all together it reaches t = 1 (docs/flow.md). Judging
// the shrink by the isotropy of the smaller supports instead was tried too (2026-12-05): the
// supports then stayed larger at the end, and the error grew as much (nx = 128, t = 1: 3.21e-4
// against 3.13e-4; it rises from t = 0.6 also while the radius is held).
Real detail::next_support_radius(Real now, Real base, Real largest, Real least_isotropy, Real target) {
  if (least_isotropy < target) return std::min(largest, 1.15 * now);
  if (least_isotropy > 2 * target) return std::max(base, now / 1.05);
  return now;
}

// Where fixed supports fail and growing ones were measured, and where warm-started volumes were
// measured to lose the late accuracy (docs/flow.md): a 2D Lagrangian flow, no walls (their layers
// were not sized for wider supports), no free surface (its particles' supports are cut by design)
// and no shifting (which keeps the supports isotropic by moving particles: the growth would never
// start). Not in 3D, where it was not measured and a support 3 times wider holds 27 times the
// neighbours.
bool FlowSolver::stretches_freely(const PointCloud& cloud) const {
  return options_.frame == FlowFrame::Lagrangian && options_.shifting.kind == Shifting::None && !options_.free_surface &&
         eq_.walls.empty() && cloud.dim == 2;
}

// Up to kAutoLargestSupport spacings, capped so that a grown support with its Verlet skin stays
// below half the shortest period; a cap below one growth step keeps the supports fixed.
Real FlowSolver::automatic_support_growth() const {
  if (!stretches_freely(ops_->cloud())) return 1;
  const Domain& box = ops_->cloud().domain;
  Real cap = kAutoLargestSupport * spacing_ / ops_->radius();
  for (int k = 0; k < box.dim; ++k)
    if (box.periodic[static_cast<std::size_t>(k)])
      cap = std::min(cap, (0.49 * box.period(k) - options_.operators.skin * ops_->radius()) / ops_->radius());
  return cap >= 1.15 ? cap : 1;
}

// The least isotropy is the last report's: finish_report measured it on these positions and
// radii (a failed step restores both), so it is not scanned again.
void FlowSolver::adapt_supports() {
  const Real now = ops_->support_radii().front();  // one radius for all
  const Real next = detail::next_support_radius(now, ops_->radius(), options_.support_growth * ops_->radius(),
                                                report_.min_support_isotropy, options_.support_isotropy_target);
  if (next != now) ops_->set_support_radii(std::vector<Real>(ops_->support_radii().size(), next));
}

std::pair<Real, Index> FlowSolver::least_isotropic_support() const {
  const Field iso = support_isotropy(ops_->cloud(), ops_->neighbours());
  std::pair<Real, Index> least{1, -1};
  for (Index i = 0; i < iso.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if ((!eq_.walls.empty() && eq_.walls.is_wall[si]) || (!surface_.surface.empty() && surface_.surface[si])) continue;
    if (least.second < 0 || iso[i] < least.first) least = {iso[i], i};
  }
  return least;
}

Real FlowSolver::max_divergence() const {
  Field div = ops_->apply(VectorOperator::Divergence, u_).col(0);
  for (const Index i : eq_.walls.index) div[i] = 0;  // a wall's one-sided row measures the wall, not the fluid
  return div.cwiseAbs().maxCoeff();
}

const FlowStepReport& FlowSolver::step(Real dt) {
  check<ConfigError>(std::isfinite(dt) && dt > 0, "flow: the time step must be positive and finite, got ", dt);
  FlowStepReport r;
  r.dt = dt;
  const Limits lim = limits();
  r.advective_number = dt * advective_bound(u_);
  r.viscous_number = dt * viscous_rate();
  r.cfl = dt * max_row_norm(u_) / spacing_;
  r.force_number = dt / force_limit();
  const Real load = r.advective_number / lim.advective + r.viscous_number / lim.viscous + r.force_number;
  if (load > 1) {
    const std::string m = detail::concat("flow step ", steps_ + 1, ": dt = ", dt, " is beyond the ", to_string(options_.scheme),
                                         " stability limit (", options_.frame == FlowFrame::Eulerian ? "advective" : "CFL",
                                         " number ", r.advective_number, " of ", lim.advective, ", viscous number ",
                                         r.viscous_number, " of ", lim.viscous,
                                         r.force_number > 0 ? detail::concat(", body-force number ", r.force_number, " of 1")
                                                            : std::string(),
                                         "; the largest stable dt is about ",
                                         stable_time_step(1.0), ")");
    check<ConfigError>(options_.allow_unstable, m, "; give a smaller dt, or allow_unstable (--allow-unstable) to run anyway");
    r.warnings.push_back(m);
  }
  const Eigen::MatrixXd un = u_;
  const Field phin = phi_, correctionn = correction_;
  const bool lagrangian = options_.frame == FlowFrame::Lagrangian;
  const std::vector<Real> radiin = options_.support_growth > 1 ? ops_->support_radii() : std::vector<Real>{};
  if (lagrangian && options_.support_growth > 1) adapt_supports();  // taken by the stages' moves
  const std::vector<Vec3> xn = ops_->cloud().positions;
  const Domain& box = ops_->cloud().domain;
  // Positions x^n + dt Σ_s a_s u_s (the stage velocities), wrapped into the box; walls stay.
  auto moved = [&](const std::vector<std::pair<Real, const Eigen::MatrixXd*>>& terms) {
    std::vector<Vec3> x = xn;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (!eq_.walls.empty() && eq_.walls.is_wall[i]) continue;
      for (const auto& [a, u] : terms)
        for (int c = 0; c < u->cols(); ++c) x[i][c] += dt * a * (*u)(static_cast<Index>(i), c);
      x[i] = box.wrap(x[i]);
    }
    return x;
  };
  try {
    // Runge–Kutta on du/dt = k(u) (and dx/dt = u, Lagrangian): each stage's rate carries its own
    // pressure (one Poisson solve per stage), and the step ends with one projection of the new
    // velocity, which removes the divergence the stages left (O(dx²) per step) instead of letting
    // it drift. Shu–Osher's form of SSP-RK3; Heun for RK2.
    Eigen::MatrixXd u_end;
    // Stage times: Heun's t, t + dt; Shu–Osher's t, t + dt, t + dt/2.
    if (options_.viscosity == FlowViscosity::Implicit) {
      u_end = imex_step(un, dt, [&](const std::vector<std::pair<Real, const Eigen::MatrixXd*>>& terms) { move_to(moved(terms), r); }, r);
    } else if (options_.scheme == FlowScheme::RK2) {
      const Eigen::MatrixXd u1 = un + dt * rate(un, t_, r);
      if (lagrangian) move_to(moved({{1.0, &un}}), r);
      u_end = 0.5 * un + 0.5 * (u1 + dt * rate(u1, t_ + dt, r));
      if (lagrangian) move_to(moved({{0.5, &un}, {0.5, &u1}}), r);
    } else {
      const Eigen::MatrixXd u1 = un + dt * rate(un, t_, r);
      if (lagrangian) move_to(moved({{1.0, &un}}), r);
      const Eigen::MatrixXd u2 = 0.75 * un + 0.25 * (u1 + dt * rate(u1, t_ + dt, r));
      if (lagrangian) move_to(moved({{0.25, &un}, {0.25, &u1}}), r);
      u_end = (1.0 / 3.0) * un + (2.0 / 3.0) * (u2 + dt * rate(u2, t_ + 0.5 * dt, r));
      if (lagrangian) move_to(moved({{1.0 / 6.0, &un}, {1.0 / 6.0, &u1}, {2.0 / 3.0, &u2}}), r);
    }
    if (options_.shifting.kind != Shifting::None || (lagrangian && options_.wall_gap > 0)) shift(u_end, dt, r);
    if (lagrangian) {
      const Index out = first_outside(ops_->cloud(), eq_.walls);
      if (out >= 0) {
        const Vec3& x = ops_->cloud().positions[static_cast<std::size_t>(out)];
        throw NumericalError(detail::concat("particle ", out, " left the box at (", x[0], ", ", x[1],
                                           ops_->cloud().dim == 3 ? detail::concat(", ", x[2]) : std::string(),
                                           "): it crossed a wall or was flung out (a smaller time step, shifting, or "
                                           "higher walls)"));
      }
    }
    u_ = project_state(u_end, r);
    check<NumericalError>(u_.allFinite(), "the velocity is no longer finite (the run is unstable: a smaller time "
                          "step, more viscosity or another method)");
    const Real energy = kinetic_energy(u_);
    check<NumericalError>(energy <= energy_bound_, "the kinetic energy grew to ", energy, " from ", energy_bound_ / 1.05,
                          " at the start, without a body force to feed it: the run is unstable (particles too "
                          "disordered for the projection: shifting; or a smaller time step, another method)");
    Eigen::Index fastest = 0;
    const Real speed = u_.rowwise().norm().maxCoeff(&fastest);
    if (!(speed <= speed_bound_)) {
      // Moving particles: say whether the supports have closed onto lines or planes (the
      // unshifted Taylor-Green vortex at its saddles, docs/flow.md), which a wider support or
      // shifting cures and a smaller step does not.
      std::string why = "advection under-resolved on this cloud: more particles or a hyperviscosity";
      if (lagrangian) {
        const auto [iso, at] = least_isotropic_support();
        const bool shifted = options_.shifting.kind != Shifting::None;
        if (iso < 0.2 || !shifted)
          why = detail::concat("particles too disordered for the projection: the smallest support isotropy is ", iso,
                               " (particle ", at, ")",
                               iso < 0.2 ? ", the supports have closed onto lines or planes: shifting, or a wider "
                                           "support (h_factor, or support_growth to widen them when they close)"
                                         : ": shifting");
        else  // shifted and no support has closed: a local instability, not the cloud's disorder
          why = detail::concat("a local instability; no support has closed (smallest isotropy ", iso, ", particle ", at,
                               ")");
      }
      const bool gravity = !options_.body_force.isZero();
      throw NumericalError(detail::concat("particle ", fastest, " reached |u| = ", speed, ", over ",
                                          options_.max_speed_growth, " times the initial largest speed",
                                          eq_.walls.empty() ? "" : " or the fastest wall's",
                                          gravity ? " plus twice the speed of a free fall across the box" : "",
                                          gravity ? "" : ", without a body force", ": the run is unstable (", why,
                                          "; or a smaller time step, another method; FlowOptions::max_speed_growth = "
                                          "0 turns this check off)"));
    }
  } catch (const Error& e) {
    u_ = un;
    phi_ = phin;
    correction_ = correctionn;
    if (!radiin.empty() && ops_->support_radii() != radiin) ops_->set_support_radii(radiin);  // before the move back
    if (lagrangian && ops_->cloud().positions != xn) {
      FlowStepReport ignored;
      move_to(xn, ignored);
    }

    rethrow_at(e, steps_ + 1, t_);
  }
  ++steps_;
  t_ += dt;
  finish_report(r);
  report_ = std::move(r);
  return report_;
}

Field FlowSolver::pressure() const { return pressure_of(forces(u_, t_), advection(*ops_, u_), t_, nullptr); }

}  // namespace vrsph
