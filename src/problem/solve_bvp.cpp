// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/config.hpp>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include "outward_normals.hpp"
#include "solve_bvp_distributed.hpp"
#include "transmissibilities.hpp"

namespace vrsph {

InfeasiblePolicy parse_infeasible_policy(const std::string& name) {
  check<ConfigError>(name == "warn" || name == "error", "--on-infeasible must be warn or error, got '", name, "'");
  return name == "warn" ? InfeasiblePolicy::Warn : InfeasiblePolicy::Error;
}

std::vector<char> tag_mask(const PointCloud& cloud, std::initializer_list<Tag> tags) {
  std::vector<char> mask(static_cast<std::size_t>(cloud.size()));
  for (std::size_t i = 0; i < mask.size(); ++i)
    mask[i] = std::find(tags.begin(), tags.end(), cloud.tags[i]) != tags.end();
  return mask;
}

BoundaryValueProblem part_of(const BoundaryValueProblem& p, Index b, Index e) {
  BoundaryValueProblem q;
  q.cloud = slice(p.cloud, b, e);  // checks the range
  const auto cut = [&](const Field& v) { return v.size() ? Field(v.segment(b, e - b)) : Field(); };
  const auto cut_rows = [&](const Eigen::MatrixXd& m) {
    return m.size() ? Eigen::MatrixXd(m.middleRows(b, e - b)) : Eigen::MatrixXd();
  };
  q.a = cut(p.a);
  q.f = cut(p.f);
  q.g = cut(p.g);
  q.q = cut(p.q);
  q.robin = cut(p.robin);
  q.mobility = cut_rows(p.mobility);
  q.grad_a = cut_rows(p.grad_a);
  q.pinned = p.pinned >= b && p.pinned < e ? p.pinned - b : -1;
  q.fix_constant = p.fix_constant;
  return q;
}

std::vector<char> unknown_mask(const PointCloud& cloud) { return tag_mask(cloud, {Tag::Interior, Tag::Neumann}); }

namespace {
void check_field(const Field& v, Index n, const char* name, bool required) {
  if (v.size() == 0 && !required) return;
  check<InputError>(v.size() == n, "boundary value problem: ", name, " has ", v.size(), " values for ", n,
                    " particles (size mismatch)");
}

// The interior particle nearest the centroid of the unknowns: pins a pure-Neumann constant.
Index centre_particle(const PointCloud& cloud, const std::vector<char>& interior) {
  Vec3 centre = Vec3::Zero();
  Index count = 0;
  for (Index i = 0; i < cloud.size(); ++i)
    if (interior[static_cast<std::size_t>(i)]) {
      centre += cloud.positions[static_cast<std::size_t>(i)];
      ++count;
    }
  if (cloud.domain.shape == Domain::Shape::Ball) centre = cloud.domain.centre;
  else if (cloud.domain.shape == Domain::Shape::Box) centre = 0.5 * (cloud.domain.lo + cloud.domain.hi);
  else if (count > 0) centre /= static_cast<Real>(count);
  Index best = -1;
  Real best_d = std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < cloud.size(); ++i)
    if (interior[static_cast<std::size_t>(i)] && (cloud.positions[static_cast<std::size_t>(i)] - centre).norm() < best_d) {
      best_d = (cloud.positions[static_cast<std::size_t>(i)] - centre).norm();
      best = i;
    }
  return best;
}
// With only Neumann data a solution exists only if the boundary flux equals the source
// (divergence theorem). Without a domain description the two integrals are estimated
// by particle quadrature: volume dx^d per interior particle (half at Neumann
// particles, which sit on the boundary) and area dx^(d-1) per Neumann particle. That
// is first-order accurate, so only a clear imbalance is reported (> 20 % of the scale).
void check_neumann_balance(const PointCloud& cloud, const Field& f, const Field& q, Real dx, BvpSolution& s) {
  const Real volume = std::pow(dx, cloud.dim), area = std::pow(dx, cloud.dim - 1);
  Real source = 0, flux = 0, scale = 0;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Tag t = cloud.tags[static_cast<std::size_t>(i)];
    if (t == Tag::Interior || t == Tag::Neumann) {
      const Real v = t == Tag::Interior ? volume : 0.5 * volume;
      source += v * f[i];
      scale += v * std::abs(f[i]);
    }
    if (t == Tag::Neumann) {
      flux += area * q[i];
      scale += area * std::abs(q[i]);
    }
  }
  s.neumann_imbalance = std::abs(flux - source) / std::max(scale, std::numeric_limits<Real>::min());
  if (s.neumann_imbalance > 0.2)
    s.warnings.push_back(detail::concat(
        "only Neumann data, and they do not balance the source: boundary flux ~ ", flux, " but integral of f ~ ", source,
        " (particle quadrature; ", s.neumann_imbalance, " of their size); a solution exists only if they are equal, so "
        "this one is not meaningful: check q and f"));
}

}  // namespace

BvpSolution solve(const BoundaryValueProblem& p, const BvpSolveOptions& o) {
#if VRSPH_HAVE_MPI  // (a build without MPI has no distributed communicator)
  if (o.communicator.distributed()) return detail::solve_distributed(p, o);
#endif
  const PointCloud& cloud = p.cloud;
  validate(cloud);
  const Index n = cloud.size();
  check_field(p.a, n, "a", false);
  check_field(p.f, n, "f", true);
  check_field(p.g, n, "g", true);
  check_field(p.robin, n, "robin", false);
  check<ConfigError>(std::isfinite(o.infeasible_tolerance) && o.infeasible_tolerance > 0,
                     "infeasible tolerance must be positive and finite, got ", o.infeasible_tolerance);
  check<ConfigError>(std::isfinite(o.h) && o.h >= 0, "support radius h must be >= 0 (0: from the h-factor), got ", o.h);
  BvpSolution s;
  s.particles = n;
  const std::vector<char> interior = tag_mask(cloud, {Tag::Interior}), flux = tag_mask(cloud, {Tag::Neumann}),
                          unknown = unknown_mask(cloud);
  s.neumann_particles = static_cast<Index>(std::count(flux.begin(), flux.end(), 1));
  if (s.neumann_particles > 0) check_field(p.q, n, "q", true);
  const bool tensor = p.mobility.size() > 0;
  check<InputError>(!tensor || p.a.size() == 0, "boundary value problem: give either a scalar coefficient a or a "
                    "tensor mobility, not both");
  const Field a = p.a.size() ? p.a : Field(Field::Ones(n));

  // Peak memory per stage: the peak since the last mark.
  const auto mark = [&](std::size_t* slot) {
    if (!o.measure_memory) return;
    if (slot) *slot = peak_resident_memory_bytes();
    reset_peak_resident_memory();
  };
  mark(nullptr);

  // Smoothing radius and neighbours.
  Stopwatch watch;
  s.spacing = o.spacing > 0 ? o.spacing : estimate_spacing(cloud);
  SearchParams sp;
  if (o.h > 0) {
    check_support_is_local(o.h, cloud_extent(cloud), 0);
    sp.radius = s.h = o.h;
  } else {
    SmoothingChoice sm = choose_smoothing(cloud, s.spacing, o.h_factor, o.h_mode, o.h_knn);
    s.h = sm.h;
    s.covering_radius = sm.covering_radius;
    sp.radius = sm.h;
    sp.radii = std::move(sm.radii);
  }
  NeighbourList nl = find_neighbours(cloud, sp);
  if (s.neumann_particles > 0) detail::check_outward_normals(cloud, nl, flux, [](Index i) { return static_cast<long long>(i); });
  s.seconds_neighbours = watch.seconds();
  mark(&s.stage_peak_bytes.neighbours);
  check_interrupt();  // a stop asked for (Ctrl-C in Python) between stages

  // Stencils: div(a grad) on the interior rows, the method's gradient on the flux rows.
  watch.restart();
  const auto method = builtin_methods().create(o.method, o.method_options);
  check<ConfigError>(method->info().supports(OperatorKind::DivAGrad), "method ", o.method, " does not provide div-a-grad");
  // Balance rows (VRSPH flux=balance): the Neumann particles' rows come with the operator.
  const bool balance = s.neumann_particles > 0 && method->balances_flux_rows(StencilUse::System);
  check<ConfigError>(s.neumann_particles == 0 || balance || method->info().supports(OperatorKind::Gradient), "method ",
                     o.method, " has no gradient stencil for Neumann rows");
  StencilRequest req;
  req.kind = OperatorKind::DivAGrad;
  req.use = StencilUse::System;
  req.coefficient = tensor ? nullptr : &a;
  req.mobility = tensor ? &p.mobility : nullptr;
  if (p.grad_a.size() && !tensor) {
    check<InputError>(p.grad_a.rows() == n && p.grad_a.cols() == cloud.dim, "grad_a must be ", n, " x ", cloud.dim,
                      ", got ", p.grad_a.rows(), " x ", p.grad_a.cols());
    check<InputError>(p.grad_a.allFinite(), "the gradient of the coefficient a is not finite");
    req.coefficient_gradient = &p.grad_a;
  }
  const std::vector<char>& operator_rows = balance ? unknown : interior;
  req.rows = operator_rows;
  const Discretisation disc{cloud, nl, o.kernel, s.spacing};
  Stencil L = method->build(disc, req);
  Stencil G;
  if (s.neumann_particles > 0 && !balance) {
    StencilRequest greq;
    greq.kind = OperatorKind::Gradient;
    greq.use = StencilUse::System;
    greq.rows = flux;
    G = method->build(disc, greq);
  }
  s.seconds_stencil = watch.seconds();
  long long nsum = 0, unknown_count = 0;
  for (Index i = 0; i < n; ++i)
    if (unknown[static_cast<std::size_t>(i)]) {
      nsum += nl.count(i);
      ++unknown_count;
    }
  s.neighbours_mean = static_cast<Real>(nsum) / static_cast<Real>(std::max<long long>(unknown_count, 1));
  nl = NeighbourList();  // not needed any more: its memory goes back before assembly and solve
  mark(&s.stage_peak_bytes.stencil);
  check_interrupt();

  // Diagnostics of the local problems (feasibility, conditioning) and of the matrix.
  // One line per kind of row; every such row, worst first, in infeasible_particles.
  const auto report = [&](const LocalResidualSummary& local, const char* what) {
    s.max_local_residual = std::max(s.max_local_residual, local.max_relative);
    s.infeasible += local.infeasible;
    if (local.infeasible == 0) return;
    for (const auto& [residual, i] : local.worst) {
      s.infeasible_particles.push_back(i);
      s.infeasible_residuals.push_back(residual);
    }
    const std::string msg = detail::infeasible_rows_warning(o.label.empty() ? o.method : o.label, local.infeasible, what,
                                                    local.worst.front().first, local.worst.front().second,
                                                    o.infeasible_tolerance);
    if (o.on_infeasible == InfeasiblePolicy::Error) throw NumericalError(msg);
    s.warnings.push_back(msg);
  };
  const std::size_t all = static_cast<std::size_t>(n);
  report(summarise_local_residuals(L, interior, o.infeasible_tolerance, all), "interior");
  if (s.neumann_particles > 0)
    report(summarise_local_residuals(balance ? L : G, flux, o.infeasible_tolerance, all),
           balance ? "Neumann (balance)" : "Neumann");
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (interior[si] && !L.condition.empty()) s.condition_max = std::max(s.condition_max, L.condition[si]);
    if (flux[si] && !G.condition.empty()) s.condition_max = std::max(s.condition_max, G.condition[si]);
  }
  // A coefficient near the floating-point range (1e300) overflows the weights: say so here
  // rather than let the solver report a NaN residual.
  for (Index i = 0; i < n; ++i) {
    if (!operator_rows[static_cast<std::size_t>(i)]) continue;
    for (Index k = L.row_begin(i); k < L.row_end(i); ++k)
      if (!std::isfinite(L.values[0][static_cast<std::size_t>(k)])) {
        const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
        throw NumericalError(detail::concat(o.label.empty() ? o.method : o.label, ": the stencil row of particle ", i,
                                            " (", x[0], ", ", x[1], ", ", x[2], ") is not finite: the coefficient or "
                                            "mobility (or 1/h^2) overflows; rescale the problem"));
      }
  }
  detail::summarise_transmissibilities(L, operator_rows, s);
  if (s.signed_rows > 0) {
    s.warnings.push_back(detail::signed_rows_warning(o.label.empty() ? o.method : o.label, s));
  } else if (method->info().monotone && s.negative_transmissibilities > 0) {
    std::string rows;
    for (std::size_t k = 0; k < s.negative_rows.size(); ++k) rows += detail::concat(k ? ", " : "", s.negative_rows[k]);
    s.warnings.push_back(detail::concat(
        o.label.empty() ? o.method : o.label, ": ", s.negative_transmissibilities, " negative off-diagonal weight(s) "
        "in interior rows of a scheme meant to be monotone: the maximum principle does not hold there (strong "
        "anisotropy or disorder; [SPE] (92)/(93), xi_max = ", s.xi_max, "); first rows: ", rows));
  }
  if (o.check_m_matrix) {
    const std::optional<Stencil> robin_rows = detail::with_robin_diagonal(L, flux, p.robin);
    const MMatrixReport mm = check_m_matrix(robin_rows ? *robin_rows : L,
                                            s.neumann_particles > 0 && !balance ? std::span<const char>(interior) : unknown);
    s.m_matrix = mm.is_m_matrix();
    s.m_matrix_summary = mm.summary();
  }

  // Assembly with Dirichlet data, flux rows and the pinned constant; then the solve.
  watch.restart();
  BoundaryRows bc;
  if (s.neumann_particles > 0) {
    bc.gradient = balance ? nullptr : &G;
    bc.coefficient = tensor ? nullptr : &a;
    bc.mobility = tensor ? &p.mobility : nullptr;
    bc.q = p.q;
    bc.robin = p.robin;
  }
  bc.pinned = p.pinned >= 0 ? p.pinned : p.fix_constant ? centre_particle(cloud, interior) : -1;
  LinearSystem sys = assemble(L, cloud, unknown, p.f, p.g, &bc);
  // The stencils are in the system now; keep only the local residuals for the report.
  if (o.keep_matrices) s.operator_rows = as_eigen(L);
  if (!L.wall_flux.empty()) s.wall_flux = Eigen::Map<const Field>(L.wall_flux.data(), n);
  s.local_residual = L.residual.empty() ? Field::Zero(n) : Field(Eigen::Map<const Field>(L.residual.data(), n));
  L = Stencil();
  G = Stencil();
  s.unknowns = sys.size();
  s.seconds_assemble = watch.seconds();
  mark(&s.stage_peak_bytes.assemble);
  check_interrupt();
  s.nnz_per_row = static_cast<Real>(sys.A.nonZeros()) / static_cast<Real>(std::max<Index>(s.unknowns, 1));

  Eigen::VectorXd x;
  SolverOptions solver = o.solver;
  if (solver.dimension == 0) solver.dimension = cloud.dim;
  s.solve = solve(sys, x, solver);
  s.seconds_solve = s.solve.seconds;
  mark(&s.stage_peak_bytes.solve);
  s.warnings.insert(s.warnings.end(), s.solve.warnings.begin(), s.solve.warnings.end());
  if (!s.solve.success)
    throw NumericalError(detail::concat("solver ", s.solve.solver, " failed for ", o.label.empty() ? o.method : o.label,
                                        ": ", s.solve.message, " (relative residual ", s.solve.residual, ")",
                                        std::isfinite(s.solve.residual) ? "" : "; the arithmetic overflowed: coefficient, "
                                        "mobility or data near the floating-point range? rescale the problem"));
  s.u = expand(sys, x);
  if (o.keep_matrices) s.system = std::move(sys);
  const bool robin = p.robin.size() > 0 && p.robin.maxCoeff() > 0;
  if (s.neumann_particles > 0 && cloud.count(Tag::Dirichlet) == 0 && !robin) check_neumann_balance(cloud, p.f, p.q, s.spacing, s);
  return s;
}

}  // namespace vrsph
