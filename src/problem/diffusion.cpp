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
  check<ConfigError>(cloud.count(Tag::Neumann) == 0, "diffusion with Neumann particles is not supported yet (",
                     cloud.count(Tag::Neumann), " in the cloud); give Dirichlet data on the whole boundary");
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

  const std::vector<char> interior = tag_mask(cloud, {Tag::Interior});
  const auto method = builtin_methods().create(o.method, o.method_options);
  StencilRequest req;
  req.kind = OperatorKind::DivAGrad;
  if (p.mobility.size()) req.mobility = &p.mobility;
  else req.coefficient = &a;
  req.rows = interior;
  const Discretisation disc{cloud, nl, o.kernel, dx};
  const Stencil L = method->build(disc, req);

  const auto boundary_values = [&](Field& u, Real t) {
    for (Index i = 0; i < n; ++i)
      if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Dirichlet) u[i] = p.boundary(cloud.positions[static_cast<std::size_t>(i)], t);
  };
  const auto source = [&](Index i, Real t) { return p.source ? p.source(cloud.positions[static_cast<std::size_t>(i)], t) : 0.0; };
  const auto record = [&](const Field& u, Real t) {
    if (o.on_step) o.on_step(t, u);
    if (!p.exact) return;
    Real e = 0;
    for (Index i = 0; i < n; ++i)
      if (interior[static_cast<std::size_t>(i)])
        e = std::max(e, std::abs(u[i] - p.exact(cloud.positions[static_cast<std::size_t>(i)], t)));
    r.times.push_back(t);
    r.error_inf.push_back(std::isfinite(u.sum()) ? e : std::numeric_limits<Real>::infinity());
  };

  Field u = p.u0;
  boundary_values(u, 0);
  record(u, 0);
  const auto steps = static_cast<Index>(std::ceil(o.t_end / o.dt - 1e-9));

  // Implicit schemes: the unknowns' block A of L, M = I - θ dt A set up once (factorised, or
  // its preconditioner built) and reused at every step, and the known neighbours'
  // contribution c(t) = Σ_{J known} L_iJ g_J(t).
  const Real theta = o.scheme == TimeScheme::Implicit ? 1.0 : 0.5;
  LinearSystem sys;
  std::unique_ptr<PreparedSolver> solver;
  if (o.scheme != TimeScheme::Explicit) {
    const std::vector<char> unknown = interior;
    sys = assemble(L, cloud, unknown, Field::Zero(n), Field::Zero(n));
    CsrMatrix M = -theta * o.dt * sys.A;
    for (Index d = 0; d < sys.size(); ++d) M.coeffRef(d, d) += 1;
    M.makeCompressed();
    SolverOptions so = o.solver;
    if (so.dimension == 0) so.dimension = cloud.dim;
    solver = std::make_unique<PreparedSolver>(M, so);
    r.solver = solver->solver();
    r.seconds_factorisation = solver->seconds_setup();
  }
  const auto known_coupling = [&](Real t) {  // c(t) at the unknowns
    Field g = Field::Zero(n);
    boundary_values(g, t);
    const Field Lg = apply_component(L, g, 0);
    Eigen::VectorXd c(sys.size());
    for (Index d = 0; d < sys.size(); ++d) c[d] = Lg[sys.particle_of_dof[static_cast<std::size_t>(d)]];
    return c;
  };

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
    } else {
      Eigen::VectorXd uU(sys.size()), rhs(sys.size());
      for (Index d = 0; d < sys.size(); ++d) uU[d] = u[sys.particle_of_dof[static_cast<std::size_t>(d)]];
      const Eigen::VectorXd c_next = known_coupling(t_next);
      for (Index d = 0; d < sys.size(); ++d) {
        const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
        rhs[d] = uU[d] + theta * o.dt * (source(i, t_next) + c_next[d]);
      }
      if (o.scheme == TimeScheme::CrankNicolson) {
        const Eigen::VectorXd Au = sys.A * uU, c_now = known_coupling(t);
        for (Index d = 0; d < sys.size(); ++d) {
          const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
          rhs[d] += 0.5 * o.dt * (Au[d] + source(i, t) + c_now[d]);
        }
      }
      Eigen::VectorXd x = uU;  // the previous step: the initial guess of iterative solvers
      const SolveReport rep = solver->solve(rhs, x);
      check<NumericalError>(rep.success, "the ", to_string(o.scheme), " step at t = ", t_next, " failed: ", rep.solver,
                            ": ", rep.message, " (relative residual ", rep.residual, ")");
      r.solver_iterations += rep.iterations;
      for (Index d = 0; d < sys.size(); ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
    }
    t = t_next;
    boundary_values(u, t);
    stepping += step_watch.seconds();
    ++r.steps;
    record(u, t);
    if (!u.allFinite()) {
      r.diverged = true;
      r.warnings.push_back(detail::concat("the solution is no longer finite at t = ", t, " (step ", r.steps,
                                          "): the explicit scheme is unstable at nu = ", r.nu));
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
