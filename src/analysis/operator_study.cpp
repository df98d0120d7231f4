// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/analysis/operator_study.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/stencil/properties.hpp>

namespace vrsph {

namespace {

Domain problem_domain(const std::string& problem, int dim) {
  if (problem == "qw-trunc") return Domain::symmetric_box(dim, 1.0);
  if (problem == "unit-box" || problem == "aar-derivative") return Domain::unit_box(dim);
  throw ConfigError("unknown operator problem '" + problem + "' (known: qw-trunc, unit-box, aar-derivative)");
}

std::vector<std::string> split_semicolons(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream is(s);
  while (std::getline(is, cur, ';')) out.push_back(cur);
  return out;
}

void validate_params(const OperatorStudyParams& p) {
  check_study_settings(p.dim, p.h_factor, p.delta, p.regular_layer);
  check<ConfigError>(!p.methods.empty(), "no method given");
  check<ConfigError>(!p.n.empty(), "empty refinement list --n");
  for (int n : p.n) check<ConfigError>(n >= 1 && n <= 20000, "refinement level n = ", n, " outside 1..20000");
  for (const auto& m : p.methods) {
    const auto& info = builtin_methods().info(m);  // throws for unknown names
    if (!info.provides(p.op)) {
      std::string which;  // the methods that do: what to pass to --method instead
      for (const MethodInfo& other : builtin_methods().list())
        if (other.provides(p.op)) which += (which.empty() ? "" : ", ") + other.name;
      throw ConfigError(detail::concat("method ", m, " does not provide operator ", to_string(p.op),
                                       which.empty() ? std::string() : " (methods that do: " + which + ")"));
    }
    (void)builtin_methods().create(m, options_for(p.method_options, m));
  }
  check<ConfigError>(p.cloud != CloudFamily::Centroids || p.dim >= 2, "the centroids cloud needs --dim 2 or 3");
  check<ConfigError>(p.cloud != CloudFamily::Disk || !p.ghosts, "the disk cloud has no ghosts: add --no-ghosts");
  if (p.problem == "aar-derivative") {
    check<ConfigError>(p.dim == 1, "problem aar-derivative is one-dimensional (--dim 1)");
    check<ConfigError>(!p.ghosts, "problem aar-derivative has no ghost particles (truncated sums at the ends, [AAR])");
  }
}

// [AAR]'s derivative test measures the error at every particle, the ends included.
// grad-div-composed applies the method's gradient rows twice: its second pass reads the first at
// every neighbour of an evaluated row, ghosts included.
bool composes_gradient_rows(const OperatorStudyParams& p) { return p.vector_op == VectorOperator::GradDivComposed; }

bool evaluates_boundary(const OperatorStudyParams& p) { return p.evaluate_boundary || p.problem == "aar-derivative"; }

// The user's --u, else the problem's test function ([AAR]: e^x, [QW]: cos).
std::string test_function_of(const OperatorStudyParams& p) {
  return !p.u.empty() ? p.u : p.problem == "aar-derivative" ? "exp-x" : "cos-pi";
}
}  // namespace

namespace {
// The functions of a study: the test function u, the coefficient a (div-a-grad) and the
// user's exact values (--exact), parsed once.
struct StudyFunctions {
  std::unique_ptr<ScalarFunction> u, a;
  std::vector<std::unique_ptr<ScalarFunction>> components;  ///< a vector operator's field
  std::vector<Expression> expected;
};

// "f, g" at the commas outside parentheses (a function's arguments stay together).
std::vector<std::string> split_components(const std::string& s) {
  std::vector<std::string> out(1);
  int depth = 0;
  for (char ch : s) {
    depth += ch == '(' ? 1 : ch == ')' ? -1 : 0;
    if (ch == ',' && depth == 0) out.emplace_back();
    else out.back() += ch;
  }
  return out;
}

int output_columns(const OperatorStudyParams& p) {
  return p.vector_op ? output_components(*p.vector_op, p.dim) : components(p.op, p.dim);
}

StudyFunctions study_functions(const OperatorStudyParams& p) {
  StudyFunctions fn;
  if (p.vector_op) {
    const auto parts = split_components(p.u);
    check<ConfigError>(static_cast<int>(parts.size()) == p.dim, "operator ", to_string(*p.vector_op), " acts on a vector "
                       "field: give --u as ", p.dim, " comma-separated components, got ", parts.size(), " ('", p.u, "')");
    for (const auto& part : parts) fn.components.push_back(make_function_or_expression(part, p.dim));
  } else {
    fn.u = make_function_or_expression(test_function_of(p), p.dim);
  }
  if (p.op == OperatorKind::DivAGrad) fn.a = make_function_or_expression(p.a.empty() ? "one-plus-r2" : p.a, p.dim);
  if (p.exact.empty()) return fn;
  // Components separated by ';', or, as in --u, by the commas outside parentheses.
  const auto exact_parts = p.exact.find(';') != std::string::npos ? split_semicolons(p.exact) : split_components(p.exact);
  for (const auto& e : exact_parts) fn.expected.emplace_back(e);
  check<InputError>(static_cast<int>(fn.expected.size()) == output_columns(p), "--exact gives ",
                    fn.expected.size(), " expression(s) but operator ",
                    p.vector_op ? to_string(*p.vector_op) : to_string(p.op), " has ", output_columns(p),
                    " component(s) in ", p.dim, "D (separate components with ';' or ',')");
  return fn;
}

// The cloud of one level, its size checked against the memory limit first.
StudyCloud level_cloud(const OperatorStudyParams& p, const Domain& box, const std::string& name, int n) {
  CloudSpec spec;
  spec.family = p.cloud;
  spec.box = box;
  spec.n = n;
  spec.delta = p.delta;
  spec.seed = p.seed;
  spec.regular_layer = p.regular_layer;
  const Real dx = (box.hi[0] - box.lo[0]) / n;
  const Real h = p.h_factor * dx;
  check_support_is_local(h, (box.hi - box.lo).norm(), p.h_factor);  // before the ghost layer grows with h
  // The method's gradient rows applied twice (grad-div-composed) read the first pass at every
  // neighbour, whose rows need a full support in turn: twice the reach. (With one reach the
  // boundary rows read ghosts whose rows were cut off: an error growing like 1/dx there,
  // 10.8, 21.9, 45.0 at n = 16, 32, 64 for VRSPH on the uniform lattice.)
  const int rings = builtin_methods().info(name).stencil_rings * (composes_gradient_rows(p) ? 2 : 1);
  const double ghost_layers = p.ghosts ? std::ceil(rings * p.h_factor + 1) : 0;
  const double particles = std::pow(n + 1.0 + 2 * ghost_layers, p.dim);
  check_run_footprint(estimate_run_footprint(p.dim, particles, p.h_factor, components(p.op, p.dim), false),
                      detail::concat("n = ", n));
  spec.layout = p.ghosts ? Layout::CellCentred : Layout::Vertex;
  // Nested (two-ring) stencils need inner derivatives with full support at every
  // neighbour: the ghost layer grows with the method's reach.
  spec.ghost_width = p.ghosts ? rings * h + dx : 0;
  return make_study_cloud(spec);
}

// ∂_b (div u) at x: fourth-order central differences of the components' gradients (step
// 1e-3 max(1, |x_b|): truncation ~1e-12 |u^(5)|, round-off ~1e-7 of the gradients' own).
Real grad_div_component(const StudyFunctions& fn, const Vec3& x, int dim, int b) {
  const Real e = 1e-3 * std::max<Real>(1, std::abs(x[b]));
  auto div = [&](Real t) {
    Vec3 y = x;
    y[b] += t;
    Real d = 0;
    for (int c = 0; c < dim; ++c) d += fn.components[static_cast<std::size_t>(c)]->gradient(y)[c];
    return d;
  };
  return (-div(2 * e) + 8 * div(e) - 8 * div(-e) + div(-2 * e)) / (12 * e);
}

// The operator's exact values at the particles: from u (and a), or the user's --exact.
// A vector operator of the components' derivatives (finite differences of the expressions).
Eigen::MatrixXd vector_exact(VectorOperator op, const StudyFunctions& fn, const PointCloud& cloud) {
  const int dim = cloud.dim;
  Eigen::MatrixXd out(cloud.size(), output_components(op, dim));
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    if (op == VectorOperator::VectorLaplacian) {
      for (int c = 0; c < dim; ++c) out(i, c) = fn.components[static_cast<std::size_t>(c)]->laplacian(x);
      continue;
    }
    if (op == VectorOperator::GradDiv || op == VectorOperator::GradDivComposed) {
      for (int b = 0; b < dim; ++b) out(i, b) = grad_div_component(fn, x, dim, b);
      continue;
    }
    std::array<Vec3, 3> g{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  // g[c] = grad u_c
    for (int c = 0; c < dim; ++c) g[static_cast<std::size_t>(c)] = fn.components[static_cast<std::size_t>(c)]->gradient(x);
    if (op == VectorOperator::Divergence) {
      out(i, 0) = 0;
      for (int c = 0; c < dim; ++c) out(i, 0) += g[static_cast<std::size_t>(c)][c];
    } else if (dim == 2) {
      out(i, 0) = g[1][0] - g[0][1];
    } else {
      out.row(i) << g[2][1] - g[1][2], g[0][2] - g[2][0], g[1][0] - g[0][1];
    }
  }
  check<InputError>(out.allFinite(), "the exact ", to_string(op), " of --u is not finite at some particle");
  return out;
}

Eigen::MatrixXd exact_values(const OperatorStudyParams& p, const StudyFunctions& fn, const PointCloud& cloud,
                             const Stencil& s) {
  Eigen::MatrixXd exact(cloud.size(), output_columns(p));
  if (fn.expected.empty() && p.vector_op) {
    exact = vector_exact(*p.vector_op, fn, cloud);
  } else if (fn.expected.empty()) {
    exact = sample_exact(p.op, *fn.u, fn.a.get(), cloud);
  } else {
    for (Index i = 0; i < cloud.size(); ++i)
      for (int c = 0; c < exact.cols(); ++c) {
        const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
        const Expression& e = fn.expected[static_cast<std::size_t>(c)];
        exact(i, c) = e(x);
        check<InputError>(std::isfinite(exact(i, c)), "--exact '", printable(e.text(), 200), "' is not finite (",
                          exact(i, c), ") at particle ", i, " (", x[0], ", ", x[1], ", ", x[2], ")");
      }
  }
  // Compact rows (VRSPH rhs=compact) approximate the average Σ_k μ_ik (L u)(x_k) of the
  // operator over their stencil, not its value at x_i: that is what they are compared with.
  if (!s.rhs.empty()) {
    check<ConfigError>(!p.vector_op || exact.cols() == 1, "compact rows (rhs=compact) apply to scalar operators");
    exact.col(0) = average_rhs(s, Field(exact.col(0)));
  }
  return exact;
}

// Which rows are evaluated, their neighbour counts and the stencil's row diagnostics.
std::vector<char> evaluated_rows(const OperatorStudyParams& p, const PointCloud& cloud, const NeighbourList& nl,
                                 const Stencil& s, int n, OperatorStudyRow& row) {
  std::vector<char> rows_mask(static_cast<std::size_t>(cloud.size()));
  Index evaluated = 0, nmin = std::numeric_limits<Index>::max(), nmax = 0;
  long long nsum = 0;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Tag tag = cloud.tags[static_cast<std::size_t>(i)];
    const bool use = tag == Tag::Interior || (evaluates_boundary(p) && tag != Tag::Ghost);
    rows_mask[static_cast<std::size_t>(i)] = use;
    if (!use) continue;
    ++evaluated;
    nsum += nl.count(i);
    nmin = std::min(nmin, nl.count(i));
    nmax = std::max(nmax, nl.count(i));
  }
  check<GeometryError>(evaluated > 0, "no interior particle to evaluate at n = ", n);
  const LocalResidualSummary local = summarise_local_residuals(s, rows_mask, 1e-6, 0);
  row.max_local_residual = local.max_relative;
  row.infeasible = local.infeasible;
  for (std::size_t i = 0; i < s.negative_volumes.size(); ++i) row.signed_rows += rows_mask[i] && s.negative_volumes[i] > 0;
  row.neighbours_mean = static_cast<Real>(nsum) / static_cast<Real>(evaluated);
  row.neighbours_min = nmin;
  row.neighbours_max = nmax;
  row.nnz_per_row = static_cast<Real>(s.nnz()) / static_cast<Real>(s.rows());
  for (Index i = 0; i < cloud.size(); ++i)
    if (!s.condition.empty() && rows_mask[static_cast<std::size_t>(i)])
      row.condition_max = std::max(row.condition_max, s.condition[static_cast<std::size_t>(i)]);
  return rows_mask;
}

// One (method, n) row of the table.
OperatorStudyRow study_level(const OperatorStudyParams& p, const Domain& box, const StudyFunctions& fn,
                             const std::string& name, const Method& method, int n) {
  OperatorStudyRow row;
  row.method = name;
  row.n = n;
  Stopwatch watch;
  const StudyCloud sc = level_cloud(p, box, name, n);
  const PointCloud& cloud = sc.cloud;
  row.seconds_cloud = watch.seconds();
  row.dx = sc.dx;
  row.total = cloud.size();
  row.particles = cloud.size() - cloud.count(Tag::Ghost);

  watch.restart();
  SmoothingChoice sm = choose_smoothing(cloud, sc.dx, p.h_factor, p.h_mode, p.h_knn);
  row.h = sm.h;
  SearchParams sp;
  sp.radius = sm.h;
  sp.radii = std::move(sm.radii);
  const NeighbourList nl = find_neighbours(cloud, sp);  // (periodic: minimum image, for the statistics)
  row.seconds_neighbours = watch.seconds();

  watch.restart();
  const Discretisation disc{cloud, nl, p.kernel, cloud.spacing};
  StencilRequest req;
  req.kind = p.op;
  // The composed operator reads its first pass at the ghosts too (their rows are otherwise not
  // built: zeros that the boundary's neighbours read).
  std::vector<char> all_rows;
  if (composes_gradient_rows(p)) {
    all_rows.assign(static_cast<std::size_t>(cloud.size()), 1);
    req.rows = all_rows;
  }
  Field a_values;
  if (fn.a) {
    a_values = sample(*fn.a, cloud);
    req.coefficient = &a_values;
  }
  const Stencil s = cloud.domain.any_periodic() ? periodic_stencil(method, cloud, sp, p.kernel, cloud.spacing, req)
                                                : build_stencil(method, disc, req);
  row.seconds_stencil = watch.seconds();

  watch.restart();
  Eigen::MatrixXd approx;
  if (p.vector_op) {
    Eigen::MatrixXd U(cloud.size(), p.dim);
    for (int c = 0; c < p.dim; ++c) U.col(c) = sample(*fn.components[static_cast<std::size_t>(c)], cloud);
    approx = apply_vector(*p.vector_op, s, U);
  } else {
    approx = apply(s, sample(*fn.u, cloud));
  }
  row.seconds_apply = watch.seconds();
  const Eigen::MatrixXd exact = exact_values(p, fn, cloud, s);
  const std::vector<char> rows_mask = evaluated_rows(p, cloud, nl, s, n, row);
  const std::vector<Real> vol(static_cast<std::size_t>(cloud.size()), std::pow(cloud.spacing, p.dim));
  row.errors = error_norms(approx - exact, rows_mask, cloud, row.h, vol);
  return row;
}
}  // namespace

OperatorStudyResult run_operator_study(const OperatorStudyParams& p) {
  validate_params(p);
  Domain box = problem_domain(p.problem, p.dim);
  box.set_periodic(p.periodic);
  const StudyFunctions fn = study_functions(p);
  OperatorStudyResult result;
  result.params = p;
  const double steps = static_cast<double>(p.methods.size() * p.n.size());
  double done = 0;
  for (const auto& name : p.methods) {
    const auto method = builtin_methods().create(name, options_for(p.method_options, name));
    std::vector<OperatorStudyRow> rows;
    for (int n : p.n) {
      rows.push_back(study_level(p, box, fn, name, *method, n));
      done += 1;
      if (p.progress) p.progress(name + " n=" + std::to_string(n), done / steps);
    }
    std::vector<Real> sizes, einf, el2;
    for (const auto& r : rows) {
      sizes.push_back(r.dx);
      einf.push_back(r.errors.all.linf);
      el2.push_back(r.errors.all.l2);
    }
    const auto oi = pairwise_orders(sizes, einf), o2 = pairwise_orders(sizes, el2);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      rows[k].order_inf = oi[k];
      rows[k].order_l2 = o2[k];
    }
    result.fitted_order_inf[name] = least_squares_order(sizes, einf);
    result.rows.insert(result.rows.end(), rows.begin(), rows.end());
  }
  return result;
}

Table to_table(const OperatorStudyResult& r) {
  Table t;
  t.columns = {"method", "n", "N", "N_total", "dx", "h", "error_inf", "order_inf", "error_l2", "order_l2", "error_rms",
               "error_inf_interior", "error_inf_boundary", "neighbours_mean", "nnz_per_row", "max_local_residual", "infeasible",
               "signed_rows", "condition_max",
               "seconds_neighbours", "seconds_stencil"};
  for (const auto& row : r.rows) {
    t.add_row({{"method", row.method},
               {"n", static_cast<long long>(row.n)},
               {"N", static_cast<long long>(row.particles)},
               {"N_total", static_cast<long long>(row.total)},
               {"dx", row.dx},
               {"h", row.h},
               {"error_inf", row.errors.all.linf},
               {"order_inf", row.order_inf},
               {"error_l2", row.errors.all.l2},
               {"order_l2", row.order_l2},
               {"error_rms", row.errors.all.rms},
               {"error_inf_interior", row.errors.interior.count ? row.errors.interior.linf : std::nan("")},
               {"error_inf_boundary", row.errors.near_boundary.count ? row.errors.near_boundary.linf : std::nan("")},
               {"neighbours_mean", row.neighbours_mean},
               {"nnz_per_row", row.nnz_per_row},
               {"max_local_residual", row.max_local_residual},
               {"infeasible", static_cast<long long>(row.infeasible)},
               {"signed_rows", static_cast<long long>(row.signed_rows)},
               {"condition_max", row.condition_max > 0 ? row.condition_max : std::nan("")},
               {"seconds_neighbours", row.seconds_neighbours},
               {"seconds_stencil", row.seconds_stencil}});
  }
  return t;
}

Json metadata_json(const OperatorStudyResult& r) {
  const auto& p = r.params;
  Json j;
  j["problem"] = p.problem;
  j["dim"] = p.dim;
  j["operator"] = std::string(p.vector_op ? to_string(*p.vector_op) : to_string(p.op));
  j["cloud"] = to_string(p.cloud);
  j["ghosts"] = p.ghosts;
  j["h_factor"] = p.h_factor;
  j["h_mode"] = to_string(p.h_mode);
  j["kernel"] = std::string(kernel_info(p.kernel).name);
  j["seed"] = p.seed;
  j["delta"] = p.delta;
  j["regular_layer"] = p.regular_layer;
  j["function"] = test_function_of(p);
  j["evaluated"] = evaluates_boundary(p) ? "all particles (boundary included)" : "interior particles";
  Json fit = Json::object();  // a NaN order is null
  for (const auto& [m, o] : r.fitted_order_inf) fit[m] = o;
  j["fitted_order_inf"] = fit;
  return j;
}

}  // namespace vrsph
