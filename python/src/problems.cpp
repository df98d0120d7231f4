// SPDX-License-Identifier: BSD-3-Clause
// Boundary value problems: one solve on a cloud (data as expressions or arrays; the Python
// layer turns callables into arrays), and the convergence study with the CLI's fields.
#include <cmath>
#include <regex>
#include <vrsph/reproduce/published_problems.hpp>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/analysis/operator_study.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/problem/from_expressions.hpp>
#include "bindings.hpp"
#include "cloud_cache.hpp"

namespace vrsph::python {

namespace {
SolverOptions to_solver(const std::string& solver, const std::string& petsc_options) {
  SolverOptions o;
  o.type = parse_solver(solver);
  o.petsc_options = petsc_options;
  check<ConfigError>(petsc_options.empty() || o.type == SolverType::Petsc || o.type == SolverType::Auto,
                     "petsc_options apply to solver 'petsc' or 'auto', not '", solver, "'");
  return o;
}

std::string text(const py::dict& d, const char* key) {
  return d.contains(key) && !d[key].is_none() ? std::string(py::str(d[key])) : std::string();
}

py::object cell(const TableCell& c) {
  return std::visit([](const auto& v) -> py::object {
    using V = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<V, std::monostate>) return py::none();
    else if constexpr (std::is_same_v<V, double>) return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none());
    else return py::cast(v);
  }, c);
}

// A message that names the CLI's data options (--q, --q-column, --u, ...) reworded with the
// parameters of vrsph.solve (q, u, ...): what a Python caller can act on.
std::string python_names(const std::string& message) {
  static const std::regex option("--(u|a|f|g|q|mobility)(-column)?\\b");
  return std::regex_replace(message, option, "the parameter $1");
}

// Arrays given for a role replace its expression (problem_from_expressions checks both are not given).
struct GivenValues {
  Field u, a, f, g, q;
  ProblemValues pointers;
};

void take_values(const py::dict& values, Index n, GivenValues& v) {
  const auto take = [&](const char* key, Field& store, const Field*& slot) {
    if (values.contains(key) && !values[key].is_none()) {
      store = field_from(values[key], n, key);
      slot = &store;
    }
  };
  take("u", v.u, v.pointers.u);
  take("a", v.a, v.pointers.a);
  take("f", v.f, v.pointers.f);
  take("g", v.g, v.pointers.g);
  take("q", v.q, v.pointers.q);
}

BvpSolveOptions solve_options(const py::dict& opt) {
  BvpSolveOptions o;
  o.method = opt["method"].cast<std::string>();
  o.method_options = method_options_from(opt["method_options"].cast<py::dict>());
  o.kernel = parse_kernel(opt["kernel"].cast<std::string>());
  o.h = opt["h"].cast<double>();
  o.h_factor = opt["h_factor"].cast<double>();
  o.h_mode = parse_smoothing_mode(opt["h_mode"].cast<std::string>());
  o.solver = to_solver(opt["solver"].cast<std::string>(), opt["petsc_options"].cast<std::string>());
  o.on_infeasible = parse_infeasible_policy(opt["on_infeasible"].cast<std::string>());
  o.infeasible_tolerance = opt["infeasible_tol"].cast<double>();
  o.keep_matrices = opt.contains("return_system") && opt["return_system"].cast<bool>();
  check<ConfigError>(std::isfinite(o.h) && o.h >= 0, "h must be >= 0 (0: h_factor x spacing), got ", o.h);
  // distributed=True: every rank of the mpirun launch passes its part of the cloud.
  if (opt.contains("distributed") && opt["distributed"].cast<bool>()) o.communicator = Communicator::world();
  return o;
}

// Robin data a du/dn + beta u = q at the Neumann particles: beta >= 0 per particle (empty: none).
Field robin_field(const py::dict& values, Index n) {
  if (!values.contains("robin") || values["robin"].is_none()) return {};
  Field robin = field_from(values["robin"], n, "robin");
  for (Index i = 0; i < n; ++i)
    check<InputError>(std::isfinite(robin[i]) && robin[i] >= 0, "robin: beta = ", robin[i], " at particle ", i,
                      " must be finite and >= 0 (a du/dn + beta u = q)");
  return robin;
}

struct SolvedProblem {
  ExpressionProblem ep;
  BvpSolution s;
  ErrorReport errors;
};

// The problem from its expressions and arrays, solved, and its errors where u is known
// (over the unknowns, split at one support radius from the boundary). Runs without the GIL.
SolvedProblem solve_expressions(const PointCloud& cloud, const ProblemExpressions& e, const ProblemValues& pv,
                                const Field& robin, bool fix_constant, const BvpSolveOptions& o) {
  const Index n = cloud.size();
  SolvedProblem x;
  try {
    x.ep = problem_from_expressions(cloud, e, pv);
  } catch (const std::exception& err) {  // the library's texts name the CLI's options
    rethrow_with_message(err, python_names(err.what()));
  }
  x.ep.problem.fix_constant = fix_constant;
  if (robin.size()) {
    // q derived from the exact u (no q given) is a du/dn: the Robin condition adds beta u.
    const bool derived = x.ep.exact.size() && !pv.q && e.q.empty();
    if (derived && x.ep.problem.q.size())
      for (Index i = 0; i < n; ++i)
        if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Neumann) x.ep.problem.q[i] += robin[i] * x.ep.exact[i];
    x.ep.problem.robin = robin;
  }
  x.s = solve(x.ep.problem, o);
  if (any_rank(o.communicator, x.ep.exact.size() > 0)) {  // (distributed: the norms over every rank's part)
    const PointCloud& c = x.ep.problem.cloud;
    Eigen::MatrixXd err(c.size(), 1);
    err.col(0) = x.s.u - x.ep.exact;
    const std::vector<Real> volumes(static_cast<std::size_t>(c.size()), std::pow(x.s.spacing, c.dim));
    const auto first = static_cast<Index>(offset_over_ranks(o.communicator, c.size()));
    x.errors = error_norms_over_ranks(err, unknown_mask(c), c, x.s.h, volumes, o.communicator, first);
  }
  return x;
}

// The assembled system A x = b over the unknowns (dof k is particle dofs[k]) and the
// operator rows, as CSR arrays for scipy.sparse (Python builds the matrices).
void add_system(const BvpSolution& s, py::dict& d) {
  const auto csr = [](const SparseMatrix& given) {
    SparseMatrix M = given;
    M.makeCompressed();
    py::dict m;
    m["indptr"] = py::array_t<int>(M.outerSize() + 1, M.outerIndexPtr());
    m["indices"] = py::array_t<int>(M.nonZeros(), M.innerIndexPtr());
    m["data"] = py::array_t<double>(M.nonZeros(), M.valuePtr());
    m["shape"] = py::make_tuple(M.rows(), M.cols());
    return m;
  };
  py::dict sys = csr(s.system.A);
  sys["rhs"] = py::array_t<double>(s.system.b.size(), s.system.b.data());
  sys["dofs"] = s.system.particle_of_dof;
  d["system"] = sys;
  d["operator_rows"] = csr(s.operator_rows);
}

py::dict solution_dict(const SolvedProblem& r, bool with_system) {
  const BvpSolution& s = r.s;
  py::dict d;
  d["u"] = py::array_t<double>(s.u.size(), s.u.data());
  d["local_residual"] = py::array_t<double>(s.local_residual.size(), s.local_residual.data());
  d["particles"] = s.particles;
  d["unknowns"] = s.unknowns;
  d["spacing"] = s.spacing;
  d["h"] = s.h;
  d["mmatrix"] = s.m_matrix;
  d["mmatrix_summary"] = s.m_matrix_summary;
  d["infeasible"] = s.infeasible;
  d["infeasible_particles"] = s.infeasible_particles;
  d["condition_max"] = s.condition_max;
  d["neumann_imbalance"] = s.neumann_imbalance;
  d["solver"] = s.solve.solver;
  d["solver_iterations"] = s.solve.iterations;
  d["solver_residual"] = s.solve.residual;
  d["solver_reason"] = s.solve.reason;
  d["warnings"] = s.warnings;
  d["infeasible_residuals"] = s.infeasible_residuals;
  if (s.wall_flux.size()) d["wall_flux"] = py::array_t<double>(s.wall_flux.size(), s.wall_flux.data());
  if (with_system) add_system(s, d);
  d["seconds_neighbours"] = s.seconds_neighbours;
  d["seconds_stencil"] = s.seconds_stencil;
  d["seconds_assemble"] = s.seconds_assemble;
  d["seconds_solve"] = s.seconds_solve;
  if (r.ep.exact.size()) {
    d["exact"] = py::array_t<double>(r.ep.exact.size(), r.ep.exact.data());
    d["error_inf"] = r.errors.all.linf;
    d["error_l2"] = r.errors.all.l2;
    d["error_inf_interior"] = r.errors.interior.linf;
    d["error_inf_boundary"] = r.errors.near_boundary.linf;
  }
  return d;
}

py::dict solve_problem(const py::object& self, const py::dict& expressions, const py::dict& values, const py::dict& opt) {
  const auto& cloud = as_cloud(self);
  const Index n = cloud.size();
  ProblemExpressions e{text(expressions, "u"), text(expressions, "a"), text(expressions, "f"), text(expressions, "g"),
                       text(expressions, "q")};
  if (expressions.contains("mobility") && !expressions["mobility"].is_none())
    e.mobility = expressions["mobility"].cast<std::vector<std::string>>();
  GivenValues given;
  take_values(values, n, given);
  BvpSolveOptions o = solve_options(opt);
  const bool fix_constant = opt["fix_constant"].cast<bool>();
  if (o.communicator.distributed()) {
    o.spacing = cloud.spacing;  // a generated part knows it; 0: estimated over every rank's part
  } else {
    validate(cloud);
    o.spacing = cached_spacing(self);  // the cloud's, computed once
  }
  const Field robin = robin_field(values, n);
  SolvedProblem r;
  {
    py::gil_scoped_release release;
    r = solve_expressions(cloud, e, given.pointers, robin, fix_constant, o);
  }
  return solution_dict(r, o.keep_matrices);
}

// Rows (the CLI's JSON fields) and metadata of a study's table.
template <class Result>
py::dict report(const Result& r, const Table& t) {
  py::list rows;
  for (const auto& row : t.rows) {
    py::dict d;
    for (std::size_t c = 0; c < t.columns.size(); ++c) d[py::str(t.columns[c])] = cell(row[c]);
    rows.append(d);
  }
  py::dict out = py::module_::import("json").attr("loads")(metadata_json(r).dump());
  out["rows"] = rows;
  return out;
}

// The study as `vrsph study` runs it: the problem's defaults for what is not given.
py::dict study(const py::dict& k) {
  BvpStudyParams p;
  p.catalogue = published_problems();  // aar-static, spe-dirichlet, spe-mixed
  const std::string u = text(k, "u"), a = text(k, "a"), f = text(k, "f");
  const bool has_mobility = k.contains("mobility") && !k["mobility"].is_none();
  const bool custom = !u.empty() || !a.empty() || !f.empty() || has_mobility;
  p.problem = k.contains("problem") && !k["problem"].is_none() ? k["problem"].cast<std::string>() : (custom ? "custom" : "qw-ex5");
  const ProblemDefaults def = problem_defaults(p.problem);
  const auto given = [&k](const char* key) { return k.contains(key) && !k[key].is_none(); };
  p.dim = given("dim") ? k["dim"].cast<int>() : def.dim;
  p.methods = k["methods"].cast<std::vector<std::string>>();
  if (k.contains("method_options")) p.method_options = per_method_options(k["method_options"]);
  p.cloud = parse_cloud_family(k["cloud"].cast<std::string>());
  p.n = k["n"].cast<std::vector<int>>();
  p.h_factor = given("h_factor") ? k["h_factor"].cast<double>() : def.h_factor;
  p.h_mode = parse_smoothing_mode(k["h_mode"].cast<std::string>());
  p.delta = given("delta") ? k["delta"].cast<double>() : def.delta;
  p.perturb_boundary = k["perturb_boundary"].cast<bool>();
  p.regular_layer = k["regular_layer"].cast<double>();
  p.kernel = given("kernel") ? parse_kernel(k["kernel"].cast<std::string>()) : def.kernel;
  if (given("neumann")) p.neumann = k["neumann"].cast<std::vector<std::string>>();
  if (given("robin")) p.robin = k["robin"].cast<std::vector<std::string>>();
  p.beta = text(k, "beta");
  p.q = text(k, "q");
  p.fix_constant = k["fix_constant"].cast<bool>();
  p.solver = to_solver(k["solver"].cast<std::string>(), k["petsc_options"].cast<std::string>());
  p.u = u;
  p.a = a;
  p.f = f;
  p.g = text(k, "g");
  if (has_mobility) p.mobility = k["mobility"].cast<std::vector<std::string>>();
  const std::string layout = given("layout") ? k["layout"].cast<std::string>() : (def.cell_layout ? "cells" : "vertex");
  check<ConfigError>(layout == "vertex" || layout == "cells", "layout must be 'vertex' or 'cells', got '", layout, "'");
  p.layout = layout == "cells" ? Layout::CellCentred : Layout::Vertex;
  p.on_infeasible = parse_infeasible_policy(k["on_infeasible"].cast<std::string>());
  p.infeasible_tolerance = k["infeasible_tol"].cast<double>();
  p.seeds.clear();
  for (long long s : k["seeds"].cast<std::vector<long long>>()) {
    check<ConfigError>(s >= 0, "seeds must be >= 0, got ", s);
    p.seeds.push_back(static_cast<std::uint64_t>(s));
  }
  const BvpStudyResult r = [&] {
    py::gil_scoped_release release;
    return run_bvp_study(p);
  }();
  py::dict out = report(r, to_table(r));
  out["warnings"] = r.warnings;
  return out;
}
// The operator study as `vrsph operator` runs it.
py::dict operator_study(const py::dict& k) {
  OperatorStudyParams p;
  const auto given = [&k](const char* key) { return k.contains(key) && !k[key].is_none(); };
  p.problem = k["problem"].cast<std::string>();
  const ProblemDefaults def = problem_defaults(p.problem);
  p.dim = given("dim") ? k["dim"].cast<int>() : def.dim;
  p.methods = k["methods"].cast<std::vector<std::string>>();
  if (k.contains("method_options")) p.method_options = per_method_options(k["method_options"]);
  p.op = parse_operator(k["operator"].cast<std::string>());
  p.cloud = parse_cloud_family(k["cloud"].cast<std::string>());
  p.n = k["n"].cast<std::vector<int>>();
  const long long seed = k["seed"].cast<long long>();
  check<ConfigError>(seed >= 0, "seed must be >= 0, got ", seed);
  p.seed = static_cast<std::uint64_t>(seed);
  p.h_factor = given("h_factor") ? k["h_factor"].cast<double>() : def.h_factor;
  p.h_mode = parse_smoothing_mode(k["h_mode"].cast<std::string>());
  p.delta = given("delta") ? k["delta"].cast<double>() : def.delta;
  p.ghosts = given("ghosts") ? k["ghosts"].cast<bool>() : def.ghosts;
  p.regular_layer = k["regular_layer"].cast<double>();
  p.kernel = given("kernel") ? parse_kernel(k["kernel"].cast<std::string>()) : def.kernel;
  p.u = text(k, "u");
  p.exact = text(k, "exact");
  p.a = text(k, "a");
  const OperatorStudyResult r = [&] {
    py::gil_scoped_release release;
    return run_operator_study(p);
  }();
  return report(r, to_table(r));
}
}  // namespace

void bind_problems(py::module_& m) {
  m.def("_operator_study", &operator_study, py::arg("params"));
  m.def("_solve", &solve_problem, py::arg("cloud"), py::arg("expressions"), py::arg("values"), py::arg("options"));
  m.def("_study", &study, py::arg("params"));
}

}  // namespace vrsph::python
