// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <memory>
#include <cmath>
#include <limits>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include <vrsph/problem/diffusion.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

TimeScheme parse_time_scheme(const std::string& name) {
  if (name == "explicit") return TimeScheme::Explicit;
  if (name == "implicit") return TimeScheme::Implicit;
  if (name == "cn") return TimeScheme::CrankNicolson;
  throw ConfigError("unknown time scheme '" + name + "' (known: explicit, implicit, cn)");
}

std::string to_string(TimeScheme s) {
  switch (s) {
    case TimeScheme::Explicit: return "explicit";
    case TimeScheme::Implicit: return "implicit";
    case TimeScheme::CrankNicolson: return "cn";
  }
  return "?";
}

namespace {
// Cubic Lagrange interpolation of y(t) at T from the four samples around it.
Real interpolate(const std::vector<Real>& t, const std::vector<Real>& y, Real T) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  if (n == 0) return std::nan("");
  const auto it = std::lower_bound(t.begin(), t.end(), T);
  std::ptrdiff_t k = it - t.begin();
  // A step time within rounding of T (dt = ν ℓ² and k dt rarely land on T exactly), on either side.
  const Real tol = 1e-12 * std::max<Real>(1, std::abs(T));
  if (k < n && std::abs(t[static_cast<std::size_t>(k)] - T) <= tol) return y[static_cast<std::size_t>(k)];
  if (k > 0 && std::abs(t[static_cast<std::size_t>(k - 1)] - T) <= tol) return y[static_cast<std::size_t>(k - 1)];
  if (k == 0 || k >= n) return std::nan("");  // outside the run
  const std::ptrdiff_t first = std::clamp<std::ptrdiff_t>(k - 2, 0, std::max<std::ptrdiff_t>(n - 4, 0));
  const std::ptrdiff_t last = std::min(first + 3, n - 1);
  Real value = 0;
  for (std::ptrdiff_t i = first; i <= last; ++i) {
    Real w = 1;
    for (std::ptrdiff_t j = first; j <= last; ++j)
      if (j != i) w *= (T - t[static_cast<std::size_t>(j)]) / (t[static_cast<std::size_t>(i)] - t[static_cast<std::size_t>(j)]);
    value += w * y[static_cast<std::size_t>(i)];
  }
  return value;
}
}  // namespace

DiffusionResult diffuse(const DiffusionProblem& p, const DiffusionOptions& o) {
  Stopwatch watch;
  const PointCloud& cloud = p.cloud;
  validate(cloud);
  const Index n = cloud.size();
  check<ConfigError>(std::isfinite(o.dt) && o.dt > 0, "time step --dt must be positive and finite, got ", o.dt);
  check<ConfigError>(std::isfinite(o.t_end) && o.t_end > 0, "end time --t-end must be positive and finite, got ", o.t_end);
  check<ConfigError>(o.t_end / o.dt <= 1e8, "t_end / dt = ", o.t_end / o.dt, " steps is more than 1e8");
  check<ConfigError>(o.dt <= o.t_end, "time step dt = ", o.dt, " is longer than the run (t_end = ", o.t_end, ")");
  for (const Real T : o.report_times)  // outside the run its error would be a silent NaN
    check<ConfigError>(std::isfinite(T) && T >= 0 && T <= o.t_end * (1 + 1e-12), "report time ", T,
                       " (--report-times) is outside the run [0, t_end = ", o.t_end, "]");
  // The work up front: every step updates every particle (an explicit step costs ~1e-8 s per
  // particle on one core here, an implicit one more). Beyond 1e11 updates a run takes hours.
  const double updates = std::ceil(o.t_end / o.dt) * static_cast<double>(n);
  check<ConfigError>(updates <= 1e11, "the run would take ", std::ceil(o.t_end / o.dt), " steps x ", n, " particles = ",
                     updates, " particle updates (hours at ~1e8 per second); raise --dt, lower --t-end or use fewer "
                     "particles");
  check<InputError>(static_cast<bool>(p.flux) || cloud.count(Tag::Neumann) == 0,
                    "the cloud has Neumann particles but no flux data q(x, t) was given");
  check<InputError>(p.u0.size() == n, "initial values u0: ", p.u0.size(), " values for ", n, " particles");
  check<InputError>(p.u0.allFinite(), "initial values u0 are not finite everywhere");
  check<InputError>(static_cast<bool>(p.boundary) || cloud.count(Tag::Dirichlet) == 0,
                    "the cloud has Dirichlet particles but no boundary data g(x, t) was given");
  check<ConfigError>(p.mobility.size() == 0 || p.a.size() == 0, "give a scalar coefficient or a mobility, not both");
  const Field a = p.a.size() ? p.a : Field(Field::Ones(n));
  check<InputError>(a.size() == n, "coefficient a: ", a.size(), " values for ", n, " particles");

  DiffusionResult r;
  r.dt = o.dt;
  const Real dx = o.spacing > 0 ? o.spacing : estimate_spacing(cloud);
  SearchParams sp;
  sp.radius = o.h_factor * dx;
  check<ConfigError>(std::isfinite(sp.radius) && sp.radius > 0, "support radius must be positive, got ", sp.radius);
  const NeighbourList nl = find_neighbours(cloud, sp);
  r.smoothing_length_min = sp.radius / kernel_info(o.kernel).support_per_smoothing_length;
  const Real a_max = p.mobility.size() ? p.mobility.maxCoeff() : a.maxCoeff();
  r.nu = o.dt * a_max / (r.smoothing_length_min * r.smoothing_length_min);
  if (o.scheme == TimeScheme::Explicit && r.nu > o.nu_limit) {
    const std::string msg = detail::concat("explicit Euler with nu = dt max(a) / l_min^2 = ", r.nu, " above the bound ",
                                           o.nu_limit, " ([SPE] Table 1: stable up to 0.25)");
    check<ConfigError>(o.allow_unstable, msg, ": lower --dt, use --scheme implicit or cn, or --allow-unstable to "
                                              "run it anyway");
    r.warnings.push_back(msg + ": running it anyway (--allow-unstable)");
  }

  const std::vector<char> interior = tag_mask(cloud, {Tag::Interior}), flux = tag_mask(cloud, {Tag::Neumann}),
                          unknown = unknown_mask(cloud);
  const bool neumann = cloud.count(Tag::Neumann) > 0;
  const auto method = builtin_methods().create(o.method, o.method_options);
  check<ConfigError>(!neumann || method->info().supports(OperatorKind::Gradient), "method ", o.method,
                     " has no gradient stencil for the Neumann rows");
  // Balance rows make a Neumann particle an evolving unknown with the flux as a source; the
  // time steppers here hold flux rows as constraints at every step. Not combined yet.
  check<ConfigError>(!neumann || !method->balances_flux_rows(StencilUse::Values), "method ", o.method, ": flux=balance is for steady "
                     "problems (study, solve); diffuse needs the gradient flux rows (flux=gradient)");
  StencilRequest req;
  req.kind = OperatorKind::DivAGrad;
  if (p.mobility.size()) req.mobility = &p.mobility;
  else req.coefficient = &a;
  req.rows = interior;
  const Discretisation disc{cloud, nl, o.kernel, dx};
  const Stencil L = method->build(disc, req);
  require_point_rows(L, "diffuse");
  Stencil G;  // the method's gradient on the Neumann rows: flux rows n·M (G u) = q, as in the steady solve
  if (neumann) {
    StencilRequest greq;
    greq.kind = OperatorKind::Gradient;
    greq.rows = flux;
    G = method->build(disc, greq);
  }

  const auto boundary_values = [&](Field& u, Real t) {
    for (Index i = 0; i < n; ++i)
      if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Dirichlet) u[i] = p.boundary(cloud.positions[static_cast<std::size_t>(i)], t);
  };
  const auto source = [&](Index i, Real t) { return p.source ? p.source(cloud.positions[static_cast<std::size_t>(i)], t) : 0.0; };
  const auto flux_data = [&](Index i, Real t) { return p.flux(cloud.positions[static_cast<std::size_t>(i)], t); };
  const auto record = [&](const Field& u, Real t) {
    if (o.on_step) o.on_step(t, u);
    if (!p.exact) return;
    Real e = 0;
    for (Index i = 0; i < n; ++i)
      if (unknown[static_cast<std::size_t>(i)])
        e = std::max(e, std::abs(u[i] - p.exact(cloud.positions[static_cast<std::size_t>(i)], t)));
    r.times.push_back(t);
    r.error_inf.push_back(std::isfinite(u.sum()) ? e : std::numeric_limits<Real>::infinity());
  };

  Field u = p.u0;
  boundary_values(u, 0);
  record(u, 0);
  const auto steps = static_cast<Index>(std::ceil(o.t_end / o.dt - 1e-9));

  // The operator over the unknowns: div(a grad) rows of the interior particles and the flux
  // rows of the Neumann particles (assembly.hpp), and the known neighbours' contribution
  // c(t) = Σ_{J known} A_iJ g_J(t) to each row.
  const bool assembled = o.scheme != TimeScheme::Explicit || neumann;
  LinearSystem sys;
  if (assembled) {
    BoundaryRows bc;
    if (neumann) {
      bc.gradient = &G;
      bc.coefficient = p.mobility.size() ? nullptr : &a;
      bc.mobility = p.mobility.size() ? &p.mobility : nullptr;
      bc.q = Field::Zero(n);
    }
    sys = assemble(L, cloud, unknown, Field::Zero(n), Field::Zero(n), neumann ? &bc : nullptr);
  }
  const auto is_flux_dof = [&](Index d) { return flux[static_cast<std::size_t>(sys.particle_of_dof[static_cast<std::size_t>(d)])] != 0; };
  const auto known_coupling = [&](Real t) {
    Field g = Field::Zero(n);
    boundary_values(g, t);
    const Field Lg = apply_component(L, g, 0);
    const Eigen::MatrixXd Gg = neumann ? apply(G, g) : Eigen::MatrixXd();
    Eigen::VectorXd c(sys.size());
    for (Index d = 0; d < sys.size(); ++d) {
      const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
      if (!flux[static_cast<std::size_t>(i)]) {
        c[d] = Lg[i];
        continue;
      }
      const Vec3& nrm = cloud.normals[static_cast<std::size_t>(i)];
      c[d] = 0;
      for (int k = 0; k < cloud.dim; ++k) c[d] += nrm[k] * (p.mobility.size() ? p.mobility(i, k) : a[i]) * Gg(i, k);
    }
    return c;
  };

  // Implicit schemes: M = I - θ dt A on the interior rows, the flux rows as they are (they
  // hold at every time), set up once (factorised, or its preconditioner built) and reused.
  // Explicit scheme with Neumann particles: after each step the flux rows are solved for the
  // Neumann values, the block A_NN set up once.
  const Real theta = o.scheme == TimeScheme::Implicit ? 1.0 : 0.5;
  std::unique_ptr<PreparedSolver> solver;
  std::vector<Index> neumann_dofs, neumann_index;  // explicit: the Neumann dofs and their block index
  SolverOptions so = o.solver;
  if (so.dimension == 0) so.dimension = cloud.dim;
  if (o.scheme != TimeScheme::Explicit) {
    CsrMatrix M = sys.A;
    for (Index d = 0; d < sys.size(); ++d) {
      if (is_flux_dof(d)) continue;
      for (CsrMatrix::InnerIterator it(M, d); it; ++it) it.valueRef() *= -theta * o.dt;
    }
    for (Index d = 0; d < sys.size(); ++d)
      if (!is_flux_dof(d)) M.coeffRef(d, d) += 1;
    M.makeCompressed();
    solver = std::make_unique<PreparedSolver>(M, so);
  } else if (neumann) {
    neumann_index.assign(static_cast<std::size_t>(sys.size()), -1);
    for (Index d = 0; d < sys.size(); ++d)
      if (is_flux_dof(d)) {
        neumann_index[static_cast<std::size_t>(d)] = static_cast<Index>(neumann_dofs.size());
        neumann_dofs.push_back(d);
      }
    std::vector<Eigen::Triplet<Real, Index>> entries;
    for (std::size_t r_ = 0; r_ < neumann_dofs.size(); ++r_)
      for (CsrMatrix::InnerIterator it(sys.A, neumann_dofs[r_]); it; ++it)
        if (neumann_index[static_cast<std::size_t>(it.col())] >= 0)
          entries.emplace_back(static_cast<Index>(r_), neumann_index[static_cast<std::size_t>(it.col())], it.value());
    CsrMatrix block(static_cast<Index>(neumann_dofs.size()), static_cast<Index>(neumann_dofs.size()));
    block.setFromTriplets(entries.begin(), entries.end());
    solver = std::make_unique<PreparedSolver>(block, so);
  }
  if (solver) {
    r.solver = solver->solver();
    r.seconds_factorisation = solver->seconds_setup();
  }
  const auto solve_step = [&](const Eigen::VectorXd& rhs, Eigen::VectorXd& x, Real t_next) {
    const SolveReport rep = solver->solve(rhs, x);
    check<NumericalError>(rep.success, "the ", to_string(o.scheme), " step at t = ", t_next, " failed: ", rep.solver,
                          ": ", rep.message, " (relative residual ", rep.residual, ")");
    r.solver_iterations += rep.iterations;
  };

  // Scales for the divergence test: the largest known value so far, and the source's size.
  const auto known_scale = [&](const Field& v) {
    Real m = 0;
    for (Index i = 0; i < n; ++i)
      if (!unknown[static_cast<std::size_t>(i)]) m = std::max(m, std::abs(v[i]));
    return m;
  };
  Real data_scale = std::max(known_scale(u), p.u0.cwiseAbs().maxCoeff()), source_scale = 0;
  for (Index i = 0; i < n; ++i)
    if (interior[static_cast<std::size_t>(i)]) source_scale = std::max(source_scale, std::abs(source(i, 0)));
  r.particles = n;
  r.seconds_setup = watch.seconds();
  double stepping = 0;
  Real t = 0;
  for (Index step = 0; step < steps; ++step) {
    Stopwatch step_watch;
    const Real t_next = o.dt * static_cast<Real>(step + 1);
    if (o.scheme == TimeScheme::Explicit) {
      const Field Lu = apply_component(L, u, 0);
      for (Index i = 0; i < n; ++i)
        if (interior[static_cast<std::size_t>(i)]) u[i] += o.dt * (Lu[i] + source(i, t));
      if (neumann) {  // A_NN u_N = q(t+) - c(t+) - A_NI u_I(t+)
        Field with_data = u;
        boundary_values(with_data, t_next);
        const Eigen::VectorXd c_next = known_coupling(t_next);
        Eigen::VectorXd rhs(static_cast<Index>(neumann_dofs.size())), x(rhs.size());
        for (std::size_t k = 0; k < neumann_dofs.size(); ++k) {
          const Index d = neumann_dofs[k];
          const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
          Real interior_part = 0;
          for (CsrMatrix::InnerIterator it(sys.A, d); it; ++it)
            if (neumann_index[static_cast<std::size_t>(it.col())] < 0)
              interior_part += it.value() * with_data[sys.particle_of_dof[static_cast<std::size_t>(it.col())]];
          rhs[static_cast<Index>(k)] = flux_data(i, t_next) - c_next[d] - interior_part;
          x[static_cast<Index>(k)] = u[i];
        }
        solve_step(rhs, x, t_next);
        for (std::size_t k = 0; k < neumann_dofs.size(); ++k)
          u[sys.particle_of_dof[static_cast<std::size_t>(neumann_dofs[k])]] = x[static_cast<Index>(k)];
      }
    } else {
      Eigen::VectorXd uU(sys.size()), rhs(sys.size());
      for (Index d = 0; d < sys.size(); ++d) uU[d] = u[sys.particle_of_dof[static_cast<std::size_t>(d)]];
      const Eigen::VectorXd c_next = known_coupling(t_next);
      for (Index d = 0; d < sys.size(); ++d) {
        const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
        rhs[d] = is_flux_dof(d) ? flux_data(i, t_next) - c_next[d] : uU[d] + theta * o.dt * (source(i, t_next) + c_next[d]);
      }
      if (o.scheme == TimeScheme::CrankNicolson) {
        const Eigen::VectorXd Au = sys.A * uU, c_now = known_coupling(t);
        for (Index d = 0; d < sys.size(); ++d) {
          if (is_flux_dof(d)) continue;
          const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
          rhs[d] += 0.5 * o.dt * (Au[d] + source(i, t) + c_now[d]);
        }
      }
      Eigen::VectorXd x = uU;  // the previous step: the initial guess of iterative solvers
      solve_step(rhs, x, t_next);
      for (Index d = 0; d < sys.size(); ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
    }
    t = t_next;
    boundary_values(u, t);
    stepping += step_watch.seconds();
    ++r.steps;
    record(u, t);
    // Divergence: not finite, or 1e8 times larger than anything the data explain (the initial
    // values, the Dirichlet values so far, and the source integrated over time).
    data_scale = std::max(data_scale, known_scale(u));
    if (!u.allFinite() || u.cwiseAbs().maxCoeff() > 1e8 * (1 + data_scale + source_scale * t)) {
      r.diverged = true;
      r.warnings.push_back(detail::concat(
          "the solution ", u.allFinite() ? "grew beyond 1e8 times its data" : "is no longer finite", " at t = ", t,
          " (step ", r.steps, "): ",
          o.scheme == TimeScheme::Explicit ? detail::concat("the explicit scheme is unstable at nu = ", r.nu)
                                           : std::string("the spatial operator with these boundary rows has growing "
                                                         "modes (not dissipative), which implicit steps do not damp")));
      break;
    }
    if (o.progress && (step % 64 == 0 || step + 1 == steps)) o.progress(t / o.t_end);
  }
  for (Real T : o.report_times) r.report_error.push_back(interpolate(r.times, r.error_inf, T));
  r.u = u;
  r.seconds = watch.seconds();
  r.seconds_per_step = r.steps ? stepping / static_cast<double>(r.steps) : 0;
  return r;
}

}  // namespace vrsph
