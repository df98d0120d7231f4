// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <memory>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/problem/diffusion.hpp>
#include <vrsph/stencil/properties.hpp>
#include "diffusion_stepper.hpp"

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

namespace {
// The problem and the options, on every rank's chunk, before any work.
void check_diffusion(const DiffusionProblem& p, const DiffusionOptions& o) {
  const Communicator& comm = o.communicator;
  const long long total = sum_over_ranks(comm, static_cast<long long>(p.cloud.size()));
  const bool neumann = any_rank(comm, p.cloud.count(Tag::Neumann) > 0), dirichlet = any_rank(comm, p.cloud.count(Tag::Dirichlet) > 0);
  collective(comm, [&] {
    if (!comm.distributed()) validate(p.cloud);  // distribute() validates each chunk (one may be empty)
    const Index n = p.cloud.size();
    check<ConfigError>(std::isfinite(o.dt) && o.dt > 0, "time step --dt must be positive and finite, got ", o.dt);
    check<ConfigError>(std::isfinite(o.t_end) && o.t_end > 0, "end time --t-end must be positive and finite, got ", o.t_end);
    check<ConfigError>(o.t_end / o.dt <= 1e8, "t_end / dt = ", o.t_end / o.dt, " steps is more than 1e8");
    check<ConfigError>(o.dt <= o.t_end, "time step dt = ", o.dt, " is longer than the run (t_end = ", o.t_end, ")");
    for (const Real T : o.report_times)  // outside the run its error would be a silent NaN
      check<ConfigError>(std::isfinite(T) && T >= 0 && T <= o.t_end * (1 + 1e-12), "report time ", T,
                         " (--report-times) is outside the run [0, t_end = ", o.t_end, "]");
    // The work up front: every step updates every particle (an explicit step costs ~1e-8 s per
    // particle on one core here, an implicit one more). Beyond 1e11 updates a run takes hours.
    const double updates = std::ceil(o.t_end / o.dt) * static_cast<double>(total);
    check<ConfigError>(updates <= 1e11, "the run would take ", std::ceil(o.t_end / o.dt), " steps x ", total,
                       " particles = ", updates, " particle updates (hours at ~1e8 per second); raise --dt, lower "
                       "--t-end or use fewer particles");
    check<InputError>(static_cast<bool>(p.flux) || !neumann,
                      "the cloud has Neumann particles but no flux data q(x, t) was given");
    check<InputError>(p.u0.size() == n, "initial values u0: ", p.u0.size(), " values for ", n, " particles");
    check<InputError>(p.u0.allFinite(), "initial values u0 are not finite everywhere");
    check<InputError>(static_cast<bool>(p.boundary) || !dirichlet,
                      "the cloud has Dirichlet particles but no boundary data g(x, t) was given");
    check<ConfigError>(p.mobility.size() == 0 || p.a.size() == 0, "give a scalar coefficient or a mobility, not both");
    check<InputError>(p.a.size() == 0 || p.a.size() == n, "coefficient a: ", p.a.size(), " values for ", n, " particles");
    check<InputError>(p.mobility.size() == 0 || p.mobility.rows() == n, "mobility: ", p.mobility.rows(), " rows for ",
                      n, " particles");
    check<ConfigError>(std::isfinite(o.h_factor) && o.h_factor > 0, "support radius factor h_factor must be positive "
                       "and finite, got ", o.h_factor);
  });
}

// The stability number ν = Δt max(a) / ℓ_min² and the explicit scheme's bounds: [SPE]'s ν ≤
// nu_limit, and Δt ρ(L) ≤ 2 on the operator itself. The second catches what ν cannot: on a
// disordered cloud one row can be many times the others (measured: VRSPH, support 2 dx, a
// perturbed 48² periodic cloud, ρ dx² = 26.6 against 6–9 at 32² and 64²), and ν = 0.1 then
// diverged while ν allowed 0.25.
void stability_number(const detail::DiffusionOperator& op, const DiffusionOptions& o, DiffusionResult& r) {
  r.smoothing_length_min = op.radius / kernel_info(o.kernel).support_per_smoothing_length;
  const Field& a = op.data.a;
  const Eigen::MatrixXd& M = op.data.mobility;
  const Real local_max = M.size() ? M.maxCoeff() : a.size() ? a.maxCoeff() : -std::numeric_limits<Real>::infinity();
  const Real a_max = max_over_ranks(op.part->comm(), local_max);
  r.nu = o.dt * a_max / (r.smoothing_length_min * r.smoothing_length_min);
  if (o.scheme != TimeScheme::Explicit) return;
  // ρ of L over the interior rows and columns (the Dirichlet and Neumann values are data or solved
  // for; under MPI each rank's block without the halo columns, the largest counting).
  const Real rho = max_over_ranks(op.part->comm(), spectral_radius(op.L, op.masks.interior));
  r.dt_limit = rho > 0 ? 2 / rho : std::numeric_limits<Real>::infinity();
  std::string msg;
  if (r.nu > o.nu_limit) {
    msg = detail::concat("explicit Euler with nu = dt max(a) / l_min^2 = ", r.nu, " above the bound ", o.nu_limit,
                         " ([SPE] Table 1: stable up to 0.25)");
  } else if (o.dt > 1.02 * r.dt_limit) {  // 2 %: the estimate's own spread
    msg = detail::concat("explicit Euler with dt = ", o.dt, " is unstable on this operator: its largest eigenvalue is "
                         "about -", rho, " (power iteration over the interior rows), so dt must stay below 2 / ",
                         rho, " = ", r.dt_limit, " (nu = ", r.nu, " is within [SPE]'s bound, which assumes a regular "
                         "stencil)");
  } else {
    return;
  }
  collective(op.part->comm(), [&] {
    check<ConfigError>(o.allow_unstable, msg, ": lower --dt, use --scheme implicit or cn, or --allow-unstable to "
                                              "run it anyway");
  });
  r.warnings.push_back(msg + ": running it anyway (--allow-unstable)");
}
}  // namespace

DiffusionProblem part_of(const DiffusionProblem& p, Index b, Index e) {
  DiffusionProblem q = p;
  q.cloud = slice(p.cloud, b, e);  // checks the range
  if (p.a.size()) q.a = p.a.segment(b, e - b);
  if (p.mobility.size()) q.mobility = p.mobility.middleRows(b, e - b);
  if (p.u0.size()) q.u0 = p.u0.segment(b, e - b);
  return q;
}

DiffusionResult diffuse(const DiffusionProblem& p, const DiffusionOptions& o) {
  Stopwatch watch;
  check_diffusion(p, o);
  const detail::DiffusionOperator op = detail::build_diffusion_operator(p, o);
  DiffusionResult r;
  r.dt = o.dt;
  stability_number(op, o, r);
  detail::DiffusionStepper stepper(op, p, o, r);
  r.particles = op.part->global_size();
  r.seconds_setup = max_over_ranks(o.communicator, watch.seconds());
  stepper.run(r);
  for (Real T : o.report_times) r.report_error.push_back(interpolate(r.times, r.error_inf, T));
  r.u = op.part->to_chunk(stepper.u());
  r.seconds = max_over_ranks(o.communicator, watch.seconds());
  return r;
}

}  // namespace vrsph
