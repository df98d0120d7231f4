// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/analysis/compatibility.hpp>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/cloud/box_faces.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/properties.hpp>

namespace vrsph {

namespace {


// The problem's functions, resolved once: built in (qw-ex5, custom) or from the catalogue.
struct ProblemFunctions {
  std::shared_ptr<const ScalarFunction> u, a, f, g;
  std::vector<std::shared_ptr<const ScalarFunction>> m;  ///< diagonal mobility (empty: scalar a)
  /// Neumann data of a problem that defines them itself (x, outward normal); else from u.
  std::function<Real(const Vec3&, const Vec3&)> flux;
};

std::string known_problems(const BvpStudyParams& p) {
  std::string names = "qw-ex5";
  for (const auto& name : p.catalogue.names) names += ", " + name;
  return names + ", custom";
}

// The catalogue's problem for p.problem, if it has one.
std::optional<StudyProblem> named_problem(const BvpStudyParams& p) {
  if (!p.catalogue.has(p.problem)) return std::nullopt;
  check<ConfigError>(p.mobility.empty(), "--mobility defines a custom problem: use it without --problem ", p.problem);
  return p.catalogue.make(p);
}

ProblemFunctions problem_functions(const BvpStudyParams& p) {
  ProblemFunctions pf;
  if (const auto named = named_problem(p)) {
    pf.u = named->u;
    pf.a = named->a;
    pf.f = named->f;
    pf.g = named->g;
    pf.flux = named->flux;
    return pf;
  }
  check<ConfigError>(p.mobility.empty() || p.problem == "custom", "--mobility defines a custom problem: use it without "
                     "--problem ", p.problem);
  if (p.problem == "qw-ex5") {
    check<ConfigError>(p.u.empty() && p.a.empty() && p.f.empty(),
                       "--u/--a/--f define a custom problem: use them without --problem qw-ex5");
    pf.u = make_function("sin-pi", p.dim);
    pf.a = make_function("one-plus-r2", p.dim);
  } else if (p.problem == "custom") {
    check<ConfigError>(!p.u.empty(), "a custom problem needs the exact solution --u (used for errors and g)");
    pf.u = make_function_or_expression(p.u, p.dim);
    pf.a = make_function_or_expression(p.a.empty() ? "one" : p.a, p.dim);
    if (!p.mobility.empty()) {
      check<ConfigError>(p.a.empty(), "--a (scalar coefficient) and --mobility (diagonal tensor) exclude each other");
      check<ConfigError>(static_cast<int>(p.mobility.size()) == p.dim, "--mobility needs one expression per direction (",
                         p.dim, " in ", p.dim, "D), got ", p.mobility.size());
      for (const auto& m : p.mobility) pf.m.push_back(make_function_or_expression(m, p.dim));
    }
  } else {
    throw ConfigError("unknown boundary value problem '" + p.problem + "' (known: " + known_problems(p) + ")");
  }
  if (!p.f.empty()) {
    pf.f = make_function_or_expression(p.f, p.dim);
  } else if (!pf.m.empty()) {
    std::vector<const ScalarFunction*> m;
    for (const auto& mk : pf.m) m.push_back(mk.get());
    pf.f = std::make_shared<DivMGradOf>(*pf.u, std::move(m));  // refers to u and m, kept alive by pf
  } else {
    pf.f = std::make_shared<DivAGradOf>(*pf.u, *pf.a);
  }
  pf.g = p.g.empty() ? pf.u : std::shared_ptr<const ScalarFunction>(make_function_or_expression(p.g, p.dim));
  return pf;
}

std::vector<std::string> neumann_faces(const BvpStudyParams& p) {
  if (!p.neumann.empty()) return p.neumann;
  const auto named = named_problem(p);
  return named ? named->neumann : std::vector<std::string>{};
}

// Every face with a flux row: the Neumann and the Robin faces.
std::vector<std::string> flux_faces(const BvpStudyParams& p) {
  std::vector<std::string> faces = neumann_faces(p);
  faces.insert(faces.end(), p.robin.begin(), p.robin.end());
  return faces;
}

// β at every particle: the expression on the particles of a Robin face, 0 elsewhere.
Field robin_coefficients(const BvpStudyParams& p, const PointCloud& cloud, Real dx) {
  if (p.robin.empty()) return {};
  const std::array<bool, 6> on = parse_box_faces(p.robin, p.dim);
  const Expression beta(p.beta);
  const Domain& box = cloud.domain;
  Field b = Field::Zero(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Neumann) continue;
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    bool robin = box.shape == Domain::Shape::Ball && on[0];
    for (int k = 0; k < p.dim && box.shape == Domain::Shape::Box; ++k)
      for (int side = 0; side < 2; ++side)
        robin = robin || (on[static_cast<std::size_t>(2 * k + side)] && std::abs(x[k] - (side ? box.hi[k] : box.lo[k])) <= 1e-9 * dx);
    if (!robin) continue;
    b[i] = beta(x);
    check<InputError>(std::isfinite(b[i]) && b[i] >= 0, "the Robin coefficient --beta '", p.beta, "' is ", b[i],
                      " at (", x[0], ", ", x[1], ", ", x[2], "); it must be finite and >= 0 (a du/dn + beta u = q with "
                      "the outward normal)");
  }
  return b;
}


}  // namespace

bool StudyProblemCatalogue::has(const std::string& name) const {
  return make && std::find(names.begin(), names.end(), name) != names.end();
}

Real support_factor(const BvpStudyParams& p) {
  const auto named = named_problem(p);
  return p.h_factor * (named ? named->support_per_h_factor : 1);
}

namespace {
void validate_params(const BvpStudyParams& p) {
  check_study_settings(p.dim, p.h_factor, p.delta, p.regular_layer);
  check<ConfigError>(!p.methods.empty(), "no method given");
  check<ConfigError>(!p.n.empty(), "empty refinement list --n");
  check<ConfigError>(!p.seeds.empty(), "empty seed list");
  for (int n : p.n) check<ConfigError>(n >= 2 && n <= 20000, "refinement level n = ", n, " outside 2..20000");
  check<ConfigError>(std::isfinite(p.infeasible_tolerance) && p.infeasible_tolerance > 0,
                     "infeasible tolerance must be positive and finite, got ", p.infeasible_tolerance);
  check<ConfigError>(p.cloud != CloudFamily::Centroids || p.dim >= 2, "the centroids cloud needs --dim 2 or 3");
  for (const auto& m : p.methods) {
    check<ConfigError>(builtin_methods().info(m).supports(OperatorKind::DivAGrad), "method ", m,
                       " does not provide div-a-grad");
    check<ConfigError>(p.mobility.empty() || builtin_methods().info(m).tensor_mobility, "method ", m,
                       " cannot take a tensor (diagonal anisotropic) mobility --mobility; use vrsph, brookshaw, cb-sph, "
                       "s-sph or m-sph, or a scalar --a");
    (void)builtin_methods().create(m, options_for(p.method_options, m));
  }
  (void)problem_functions(p);  // parse expressions now
  (void)parse_box_faces(neumann_faces(p), p.dim);
  (void)parse_box_faces(p.robin, p.dim);
  for (const auto& f : p.robin)
    for (const auto& g : neumann_faces(p))
      check<ConfigError>(f != g && f != "all" && g != "all", "face ", f == "all" ? g : f,
                         " is both Neumann and Robin: give each face one condition");
  check<ConfigError>(p.robin.empty() == p.beta.empty(), p.robin.empty() ? "--beta needs Robin faces (--robin FACES)"
                                                                        : "--robin needs the coefficient --beta EXPR");
  if (!p.beta.empty()) (void)Expression(p.beta);
  check<ConfigError>(p.cloud != CloudFamily::Disk || flux_faces(p).empty() || flux_faces(p) == std::vector<std::string>{"all"},
                     "on the disk cloud the only Neumann face is 'all' (and the only Robin face)");
  if (!p.q.empty()) (void)Expression(p.q);
  check<ConfigError>(p.q.empty() || !flux_faces(p).empty(),
                     "--q gives Neumann data, but no face is Neumann: add --neumann FACES (or drop --q)");
  for (const auto& m : p.methods)
    if (!flux_faces(p).empty())
      check<ConfigError>(builtin_methods().info(m).supports(OperatorKind::Gradient), "method ", m,
                         " has no gradient stencil for Neumann rows");
}

// The flux of the exact solution: a ∇u·n, or n·M∇u with a diagonal mobility, or the
// problem's own data.
Real natural_flux(const ProblemFunctions& pf, const Vec3& x, const Vec3& normal) {
  if (pf.flux) return pf.flux(x, normal);
  const Vec3 gu = pf.u->gradient(x);
  if (pf.m.empty()) return pf.a->value(x) * gu.dot(normal);
  Real q = 0;
  for (std::size_t k = 0; k < pf.m.size(); ++k) q += normal[static_cast<int>(k)] * pf.m[k]->value(x) * gu[static_cast<int>(k)];
  return q;
}

// div(a grad u) = f with a du/dn = q everywhere has a solution only if the flux
// balances the source; otherwise the pinned solve returns a meaningless field.
void check_neumann_compatibility(const BvpStudyParams& p, const ProblemFunctions& pf, const Domain& domain) {
  if (domain.shape == Domain::Shape::None) return;
  std::unique_ptr<Expression> q_expr = p.q.empty() ? nullptr : std::make_unique<Expression>(p.q);
  const NeumannBalance nb = neumann_balance(
      domain, [&](const Vec3& x) { return pf.f->value(x); },
      [&](const Vec3& x, const Vec3& normal) {
        return q_expr ? (*q_expr)(x) : natural_flux(pf, x, normal);
      });
  check<InputError>(std::isfinite(nb.flux) && std::isfinite(nb.source), "the Neumann data q or the source f is not "
                    "finite somewhere on the domain (integral of q = ", nb.flux, ", of f = ", nb.source, ")");
  check<InputError>(nb.compatible(), "the pure-Neumann problem has no solution: the boundary flux (integral of q over "
                    "the boundary) = ", nb.flux, " must equal the source (integral of f over the domain) = ", nb.source,
                    " (divergence theorem); check --q", p.q.empty() ? "" : " '" + p.q + "'", " and --f");
}
}  // namespace

namespace {
// The run's memory estimate against the limit, before the cloud is made.
void check_run_size(const BvpStudyParams& p, int n) {
  check_support_is_local(support_factor(p) / n, std::sqrt(static_cast<Real>(p.dim)), p.h_factor);  // [0,1]^d's diameter
  const double particles = study_particles(p, n);
  check_run_footprint(estimate_run_footprint(p.dim, particles / p.communicator.size(), support_factor(p), 1, true, p.solver.type),
                      detail::concat("n = ", n));
}

// The cloud of this run (distributed: this rank's part of the serial numbering), flux faces tagged.
StudyCloud study_cloud(const BvpStudyParams& p, int n, std::uint64_t seed, BvpRun& run) {
  CloudSpec spec;
  spec.family = p.cloud;
  spec.box = Domain::unit_box(p.dim);
  spec.box.set_periodic(p.periodic);
  for (const auto& face : flux_faces(p))
    check<ConfigError>(face.size() < 2 || face[0] < 'x' || face[0] > 'z' || !spec.box.periodic[static_cast<std::size_t>(face[0] - 'x')],
                       "face ", face, " lies on a periodic axis: it is no boundary (drop it from --neumann/--robin)");
  spec.n = n;
  spec.layout = p.layout;
  spec.delta = p.delta;
  spec.seed = seed;
  spec.perturb_boundary = p.perturb_boundary;
  spec.regular_layer = p.regular_layer;
  spec.communicator = p.communicator;
  StudyCloud sc = make_study_cloud(spec);  // (collective)
  collective(p.communicator, [&] {
    run.neumann_particles = retag_neumann_faces(sc.cloud, parse_box_faces(flux_faces(p), p.dim), sc.dx);
  });
  run.neumann_particles = static_cast<Index>(sum_over_ranks(p.communicator, static_cast<long long>(run.neumann_particles)));
  run.first_id = sc.first;
  run.dx = sc.dx;
  run.particles = sc.total;
  return sc;
}

// The problem's data sampled at the particles; returns the exact solution there.
Field sample_data(const BvpStudyParams& p, const ProblemFunctions& pf, const std::string& method_name,
                  const BvpRun& run, BoundaryValueProblem& bvp) {
  const PointCloud& cloud = bvp.cloud;
  // u first: a u that is not finite must be named as the user wrote it, not through
  // the derived f = div(a grad u).
  Field exact = sample(*pf.u, cloud, "the exact solution u (--u)");
  if (pf.m.empty()) {
    bvp.a = sample(*pf.a, cloud, "the coefficient a (--a)");
  } else {
    bvp.mobility.resize(cloud.size(), p.dim);
    for (int k = 0; k < p.dim; ++k)
      bvp.mobility.col(k) = sample(*pf.m[static_cast<std::size_t>(k)], cloud, detail::concat("the mobility m_", k + 1, " (--mobility)"));
  }
  // Taylor-type methods use a Δu + ∇a·∇u with ∇a analytic when available (METHODS §3.0);
  // sampled only for them (an expression's gradient costs 4d evaluations per particle).
  if (pf.m.empty() && builtin_methods().create(method_name, options_for(p.method_options, method_name))->needs_coefficient_gradient(StencilUse::System))
    bvp.grad_a = sample_gradient(*pf.a, cloud);
  bvp.f = sample(*pf.f, cloud, "the right-hand side f (--f, default div(a grad u))");
  bvp.g = sample(*pf.g, cloud, "the Dirichlet data g (--g, default u)");
  bvp.fix_constant = p.fix_constant;
  if (run.neumann_particles == 0) return exact;
  bvp.q = Field::Zero(cloud.size());
  std::unique_ptr<Expression> q_expr = p.q.empty() ? nullptr : std::make_unique<Expression>(p.q);
  bvp.robin = robin_coefficients(p, cloud, run.dx);
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Neumann) continue;
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    bvp.q[i] = q_expr ? (*q_expr)(x) : natural_flux(pf, x, cloud.normals[static_cast<std::size_t>(i)]) +
                                           (bvp.robin.size() ? bvp.robin[i] * exact[i] : 0.0);
  }
  if (sum_over_ranks(p.communicator, static_cast<long long>(cloud.count(Tag::Dirichlet))) == 0 && p.robin.empty())
    check_neumann_compatibility(p, pf, cloud.domain);
  return exact;
}

BvpSolveOptions solve_options(const BvpStudyParams& p, const std::string& method_name, int n, std::uint64_t seed,
                              Real dx) {
  BvpSolveOptions so;
  so.method = method_name;
  so.method_options = options_for(p.method_options, method_name);
  so.kernel = p.kernel;
  so.h_factor = support_factor(p);
  so.h_mode = p.h_mode;
  so.h_knn = p.h_knn;
  so.spacing = dx;
  so.solver = p.solver;
  so.solver.dimension = p.dim;
  so.on_infeasible = p.on_infeasible;
  so.infeasible_tolerance = p.infeasible_tolerance;
  so.check_m_matrix = p.check_m_matrix;
  so.measure_memory = p.measure_memory;
  so.label = detail::concat(method_name, " n=", n, " seed=", seed);
  so.communicator = p.communicator;
  return so;
}

void record_solution(const BvpSolution& sol, BvpRun& run) {
  run.distribution = sol.distribution;
  run.h = sol.h;
  run.covering_radius = sol.covering_radius;
  run.unknowns = sol.unknowns;
  run.neighbours_mean = sol.neighbours_mean;
  run.nnz_per_row = sol.nnz_per_row;
  run.infeasible = sol.infeasible;
  run.infeasible_particles = sol.infeasible_particles;
  run.infeasible_residuals = sol.infeasible_residuals;
  run.max_local_residual = sol.max_local_residual;
  run.condition_max = sol.condition_max;
  run.m_matrix = sol.m_matrix;
  run.m_matrix_summary = sol.m_matrix_summary;
  run.negative_transmissibilities = sol.negative_transmissibilities;
  run.xi_max = sol.xi_max;
  run.solve = sol.solve;
  run.seconds_neighbours = sol.seconds_neighbours;
  run.seconds_stencil = sol.seconds_stencil;
  run.seconds_assemble = sol.seconds_assemble;
  run.seconds_solve = sol.seconds_solve;
  run.stage_peak_bytes = sol.stage_peak_bytes;
}

// The error norms over the unknowns and [SPE](95), equal volumes, over the interior
// particles ([SPE]'s DoF are the n^d cells).
void record_errors(const BvpStudyParams& p, const PointCloud& cloud, const Field& U, const Field& exact, BvpRun& run) {
  const Communicator& comm = p.communicator;
  Eigen::MatrixXd err(cloud.size(), 1);
  err.col(0) = U - exact;
  remove_periodic_constant(err, cloud, comm);  // u up to a constant on a fully periodic box
  const std::vector<Real> vol(static_cast<std::size_t>(cloud.size()), std::pow(cloud.spacing, p.dim));
  run.errors = error_norms_over_ranks(err, unknown_mask(cloud), cloud, run.h, vol, comm, run.first_id);
  Real sum = 0;
  Index count = 0;
  for (Index i = 0; i < cloud.size(); ++i)
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Interior) {
      const Real rel = exact[i] != 0 ? err(i, 0) / exact[i] : std::nan("");
      sum += rel * rel;
      ++count;
    }
  sum = sum_over_ranks(comm, sum);
  count = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(count)));
  run.error_rel = count ? std::sqrt(sum / static_cast<Real>(count)) : std::nan("");
  run.dof = count;
}

BvpRun run_validated(const BvpStudyParams& p, const std::string& method_name, int n, std::uint64_t seed,
                     bool keep_fields, std::vector<std::string>* warnings, PointCloud* cloud_out) {
  const ProblemFunctions pf = problem_functions(p);
  BvpRun run;
  run.method = method_name;
  run.n = n;
  run.seed = seed;
  Stopwatch watch;
  check_run_size(p, n);
  if (p.measure_memory) {
    release_free_memory();  // what earlier runs freed is not this run's
    run.resident_bytes_before = resident_memory_bytes();
    reset_peak_resident_memory();
  }
  BoundaryValueProblem bvp;
  bvp.cloud = std::move(study_cloud(p, n, seed, run).cloud);
  const PointCloud& cloud = bvp.cloud;
  run.seconds_cloud = watch.seconds();
  if (p.measure_memory) run.peak_bytes_cloud = peak_resident_memory_bytes();

  watch.restart();
  const Field exact = sample_data(p, pf, method_name, run, bvp);
  run.seconds_data = watch.seconds();

  const BvpSolution sol = solve(bvp, solve_options(p, method_name, n, seed, run.dx));
  if (warnings) warnings->insert(warnings->end(), sol.warnings.begin(), sol.warnings.end());
  record_solution(sol, run);
  watch.restart();
  record_errors(p, cloud, sol.u, exact, run);
  run.seconds_data += watch.seconds();
  if (keep_fields) {
    run.U = sol.u;
    run.exact = exact;
    run.local_residual = sol.local_residual;
  }
  if (cloud_out) *cloud_out = cloud;
  run.peak_memory_mib = max_over_ranks(p.communicator, static_cast<double>(peak_resident_memory_bytes()) / (1024.0 * 1024.0));
  return run;
}
}  // namespace

double study_particles(const BvpStudyParams& p, int n) {
  const double per_side = p.cloud == CloudFamily::Disk ? n / 2.0 : n + 1.0;
  return p.cloud == CloudFamily::Disk ? (p.dim == 1 ? 2 * per_side : p.dim == 2 ? 3.2 * per_side * per_side
                                                                               : 4.2 * per_side * per_side * per_side)
                                      : std::pow(per_side, p.dim);
}

StudySize checked_study_size(const BvpStudyParams& p) {
  validate_params(p);
  StudySize size;
  for (const int n : p.n) {
    check_run_size(p, n);
    size.particles = std::max(size.particles, static_cast<Index>(study_particles(p, n)));
  }
  const SolverType t = p.solver.type == SolverType::Auto ? resolve_auto(size.particles, p.dim, p.solver.auto_direct_max)
                                                         : p.solver.type;
  size.petsc = t == SolverType::Petsc;
  return size;
}

BvpRun run_bvp(const BvpStudyParams& p, const std::string& method_name, int n, std::uint64_t seed, bool keep_fields,
               std::vector<std::string>* warnings, PointCloud* cloud_out) {
  validate_params(p);
  return run_validated(p, method_name, n, seed, keep_fields, warnings, cloud_out);
}

BvpStudyResult run_bvp_study(const BvpStudyParams& p) {
  validate_params(p);
  BvpStudyResult result;
  result.params = p;
  const bool random = p.cloud == CloudFamily::Perturbed || p.cloud == CloudFamily::Centroids;
  const std::vector<std::uint64_t> seeds = random ? p.seeds : std::vector<std::uint64_t>{p.seeds.front()};
  const double total = static_cast<double>(p.methods.size() * p.n.size() * seeds.size());
  double done = 0;
  for (const auto& m : p.methods) {
    std::vector<BvpStudyRow> rows;
    for (int n : p.n) {
      BvpStudyRow row;
      std::vector<Real> einf, erel;
      Real el2 = 0, ein = 0, ebd = 0;
      for (std::size_t s = 0; s < seeds.size(); ++s) {
        check_interrupt();  // between runs: a stop asked for (Ctrl-C in Python)
        BvpRun r = run_validated(p, m, n, seeds[s], false, &result.warnings, nullptr);
        einf.push_back(r.errors.all.linf);
        erel.push_back(r.error_rel);
        row.negative_transmissibilities_max = std::max(row.negative_transmissibilities_max, r.negative_transmissibilities);
        row.xi_max = s == 0 ? r.xi_max : std::max(row.xi_max, r.xi_max);
        el2 += r.errors.all.l2;
        ein += r.errors.interior.count ? r.errors.interior.linf : 0;
        ebd += r.errors.near_boundary.count ? r.errors.near_boundary.linf : 0;
        row.m_matrix_all = row.m_matrix_all && r.m_matrix;
        row.infeasible_max = std::max(row.infeasible_max, r.infeasible);
        if (s == 0) row.first = std::move(r);
        done += 1;
        if (p.progress) p.progress(m + " n=" + std::to_string(n), done / total);
      }
      const auto k = static_cast<Real>(einf.size());
      row.seeds = static_cast<int>(einf.size());
      for (Real e : einf) row.error_inf += e / k;
      for (Real e : einf) row.error_inf_std += (e - row.error_inf) * (e - row.error_inf);
      row.error_inf_std = einf.size() > 1 ? std::sqrt(row.error_inf_std / (k - 1)) : 0;
      row.error_inf_min = *std::min_element(einf.begin(), einf.end());
      row.error_inf_max = *std::max_element(einf.begin(), einf.end());
      row.error_l2 = el2 / k;
      for (Real e : erel) row.error_rel += e / k;
      for (Real e : erel) row.error_rel_std += (e - row.error_rel) * (e - row.error_rel);
      row.error_rel_std = erel.size() > 1 ? std::sqrt(row.error_rel_std / (k - 1)) : 0;
      row.error_inf_interior = ein / k;
      row.error_inf_boundary = ebd / k;
      rows.push_back(std::move(row));
    }
    std::vector<Real> sizes, einf, el2, erel;
    for (const auto& r : rows) {
      sizes.push_back(r.first.dx);
      einf.push_back(r.error_inf);
      el2.push_back(r.error_l2);
      erel.push_back(r.error_rel);
    }
    const auto oi = pairwise_orders(sizes, einf), o2 = pairwise_orders(sizes, el2), orel = pairwise_orders(sizes, erel);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      rows[k].order_inf = oi[k];
      rows[k].order_l2 = o2[k];
      rows[k].order_rel = orel[k];
    }
    result.fitted_order_inf[m] = least_squares_order(sizes, einf);
    for (auto& r : rows) result.rows.push_back(std::move(r));
  }
  return result;
}

Table to_table(const BvpStudyResult& r) {
  Table t;
  t.columns = {"method", "n", "N", "unknowns", "dof", "h", "covering_radius", "seeds", "error_inf", "error_inf_std", "error_inf_min", "error_inf_max", "order_inf", "error_l2",
               "order_l2", "error_rel", "error_rel_std", "order_rel", "error_inf_interior", "error_inf_boundary", "mmatrix",
               "negative_transmissibilities", "xi_max", "infeasible", "condition_max", "neighbours_mean",
               "nnz_per_row", "solver", "solver_iterations", "solver_residual", "solver_reason", "seconds_cloud", "seconds_data", "seconds_neighbours", "seconds_stencil",
               "seconds_assemble", "seconds_setup", "seconds_solve", "seconds_total", "peak_memory_mib"};
  for (const auto& row : r.rows) {
    const BvpRun& f = row.first;
    t.add_row({{"method", f.method},
               {"n", static_cast<long long>(f.n)},
               {"N", static_cast<long long>(f.particles)},
               {"unknowns", static_cast<long long>(f.unknowns)},
               {"dof", static_cast<long long>(f.dof)},
               {"h", f.h},
               {"covering_radius", f.covering_radius > 0 ? f.covering_radius : std::nan("")},
               {"seeds", static_cast<long long>(row.seeds)},
               {"error_inf", row.error_inf},
               {"error_inf_std", row.error_inf_std},
               {"error_inf_min", row.error_inf_min},
               {"error_inf_max", row.error_inf_max},
               {"order_inf", row.order_inf},
               {"error_l2", row.error_l2},
               {"order_l2", row.order_l2},
               {"error_rel", row.error_rel},
               {"error_rel_std", row.error_rel_std},
               {"order_rel", row.order_rel},
               {"error_inf_interior", row.error_inf_interior},
               {"error_inf_boundary", row.error_inf_boundary},
               {"mmatrix", row.m_matrix_all},
               {"negative_transmissibilities", static_cast<long long>(row.negative_transmissibilities_max)},
               {"xi_max", row.xi_max},
               {"infeasible", static_cast<long long>(row.infeasible_max)},
               {"condition_max", f.condition_max > 0 ? f.condition_max : std::nan("")},
               {"neighbours_mean", f.neighbours_mean},
               {"nnz_per_row", f.nnz_per_row},
               {"solver", f.solve.solver},
               {"solver_iterations", static_cast<long long>(f.solve.iterations)},
               {"solver_residual", f.solve.residual},
               {"solver_reason", f.solve.reason},
               {"seconds_cloud", f.seconds_cloud},
               {"seconds_data", f.seconds_data},
               {"seconds_neighbours", f.seconds_neighbours},
               {"seconds_stencil", f.seconds_stencil},
               {"seconds_assemble", f.seconds_assemble},
               {"seconds_setup", f.solve.seconds_setup},
               {"seconds_solve", f.seconds_solve},
               {"seconds_total", f.seconds_cloud + f.seconds_data + f.seconds_neighbours + f.seconds_stencil +
                                     f.seconds_assemble + f.seconds_solve},
               {"peak_memory_mib", f.peak_memory_mib}});
  }
  return t;
}

Json metadata_json(const BvpStudyResult& r) {
  const auto& p = r.params;
  Json j;
  j["problem"] = p.problem;
  j["dim"] = p.dim;
  j["cloud"] = to_string(p.cloud);
  j["h_factor"] = p.h_factor;
  j["support_factor"] = support_factor(p);
  j["layout"] = p.layout == Layout::Vertex ? "vertex" : "cells";
  j["h_mode"] = to_string(p.h_mode);
  j["kernel"] = std::string(kernel_info(p.kernel).name);
  j["solver"] = to_string(p.solver.type);
  j["seeds"] = p.seeds;
  j["delta"] = p.delta;
  j["regular_layer"] = p.regular_layer;
  j["neumann_faces"] = neumann_faces(p);
  if (!p.robin.empty()) {
    j["robin_faces"] = p.robin;
    j["beta"] = p.beta;
  }
  if (!p.q.empty()) j["q"] = p.q;
  j["fix_constant"] = p.fix_constant;
  if (p.problem == "custom") {
    j["u"] = p.u;
    if (p.mobility.empty()) j["a"] = p.a.empty() ? "one" : p.a;
    else j["mobility"] = p.mobility;
    j["f"] = p.f.empty() ? "div(a grad u) of u and a" : p.f;
    j["g"] = p.g.empty() ? "u" : p.g;
  }
  Json fit = Json::object();  // a NaN order is null
  for (const auto& [m, o] : r.fitted_order_inf) fit[m] = o;
  j["fitted_order_inf"] = fit;
  j["warnings"] = r.warnings;
  return j;
}

}  // namespace vrsph
