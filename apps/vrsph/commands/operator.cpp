// SPDX-License-Identifier: BSD-3-Clause
// `vrsph operator`: truncation-error study of operator stencils over a refinement list.
#include <iostream>
#include <cmath>
#include <vrsph/reproduce/im_table1.hpp>
#include <vrsph/analysis/operator_study.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/gpm/gpm.hpp>
#include <vrsph/methods/gpm/gpm_at.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include <vrsph/stencil/apply.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#include "spe_patch_args.hpp"

namespace vrsph::cli {

namespace {
struct OperatorArgs {
  std::string problem = "qw-trunc", methods = "vrsph", op = "laplacian", cloud = "uniform", n = "8,16,32,64,128",
              kernel = "cubic", u, exact, a, periodic;
  int dim = 2;
  std::uint64_t seed = 1;
  double h_factor = 3, delta = 0.5;
  bool no_ghosts = false;
  std::string h_mode = "fixed";
  int h_knn = 0;
  double regular_layer = 0;
  std::vector<std::string> method_opts;
  std::string cloud_file;
  SpePatchArgs patch;
  std::string at;  // --at points.csv: gpm at arbitrary points
  std::string im_weights = "pi1,pi2,pi3,grad1,grad2,grad3,delta1,delta2,delta3", im_m = "1,3,5", im_levels = "5,6,7,8";
  long long im_points = 10000;
  std::string im_volumes = "uniform";
  OutputOptions out;
  CLI::Option *dim_opt = nullptr, *kernel_opt = nullptr, *h_factor_opt = nullptr, *delta_opt = nullptr,
              *ghosts_opt = nullptr, *h_knn_opt = nullptr;
};
// `vrsph operator --cloud-file`: the operator's error on the user's cloud, interior
// particles (full supports) apart from the tagged boundary ones (truncated supports).
void operator_on_cloud_file(const OperatorArgs& a, const CLI::App& cmd) {
  for (const char* opt : {"--problem", "--cloud", "--n", "--seed", "--delta", "--regular-layer", "--no-ghosts", "--exact"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply with --cloud-file (the cloud comes from the file; "
                                             "the expected values are the exact derivatives of --u)");
  check_h_knn_applies(a.h_knn_opt, a.h_mode);
  const PointCloud cloud = read_cloud_file(a.cloud_file, a.dim_opt->count() ? a.dim : 0).cloud;
  const OperatorKind op = parse_operator(a.op);
  const auto methods = parse_name_list(a.methods, "--method");
  const auto options = parse_method_options(a.method_opts, methods);
  note_row_forms(methods, options, StencilUse::Values);
  const auto u = make_function_or_expression(a.u.empty() ? "cos-pi" : a.u, cloud.dim);
  const auto coef = make_function_or_expression(a.a.empty() ? "one-plus-r2" : a.a, cloud.dim);
  const Field values = sample(*u, cloud);
  const Field coefficient = sample(*coef, cloud);
  const Eigen::MatrixXd exact = sample_exact(op, *u, coef.get(), cloud);
  const Real dx = estimate_spacing(cloud);
  const SmoothingChoice sm = choose_smoothing(cloud, dx, a.h_factor, parse_smoothing_mode(a.h_mode), a.h_knn);
  SearchParams sp;
  sp.radius = sm.h;
  sp.radii = sm.radii;
  const NeighbourList nl = find_neighbours(cloud, sp);
  const std::vector<char> interior = tag_mask(cloud, {Tag::Interior}),
                          boundary = tag_mask(cloud, {Tag::Dirichlet, Tag::Neumann});
  Table t;
  t.columns = {"method", "particles", "interior", "spacing", "h", "error_inf", "error_inf_boundary", "max_local_residual",
               "infeasible"};
  for (const auto& m : methods) {
    const auto method = builtin_methods().create(m, options_for(options, m));
    StencilRequest req;
    req.kind = op;
    if (op == OperatorKind::DivAGrad) req.coefficient = &coefficient;
    const Stencil s = build_stencil(*method, {cloud, nl, parse_kernel(a.kernel), dx}, req);
    Eigen::MatrixXd target = exact;
    if (!s.rhs.empty()) target.col(0) = average_rhs(s, Field(exact.col(0)));  // compact rows: against the average
    const Eigen::MatrixXd err = apply(s, values) - target;
    Real e_in = 0, e_b = 0;
    for (Index i = 0; i < cloud.size(); ++i) {
      const Real e = err.row(i).cwiseAbs().maxCoeff();
      if (interior[static_cast<std::size_t>(i)]) e_in = std::max(e_in, e);
      if (boundary[static_cast<std::size_t>(i)]) e_b = std::max(e_b, e);
    }
    const LocalResidualSummary local = summarise_local_residuals(s, interior, 1e-6);
    t.add_row({{"method", m}, {"particles", static_cast<long long>(cloud.size())},
               {"interior", static_cast<long long>(cloud.count(Tag::Interior))}, {"spacing", dx}, {"h", sm.h},
               {"error_inf", e_in}, {"error_inf_boundary", e_b}, {"max_local_residual", local.max_relative},
               {"infeasible", static_cast<long long>(local.infeasible)}});
  }
  emit(t, a.out, Json(), "h", "error_inf", "method", "operator on " + a.cloud_file);
}

// `vrsph operator --at points.csv`: [IM] (2)-(4) of gpm at arbitrary points, against the
// exact value, gradient and Laplacian of --u there. The particles: --cloud-file, or the
// --cloud family on the unit box at one --n with ghost layers covering the support.
void operator_at_points(const OperatorArgs& a, const CLI::App& cmd) {
  for (const char* opt : {"--problem", "--exact", "--a", "--operator", "--h-mode", "--h-knn", "--kernel", "--no-ghosts", "--plot"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply with --at (gpm's interpolant, gradient and Laplacian "
                       "are all evaluated against the exact derivatives of --u)");
  check<ConfigError>(a.methods == "gpm", "--at evaluates --method gpm only (the operators of [IM] at arbitrary points), got '",
                     a.methods, "'");
  const auto options = parse_method_options(a.method_opts, {"gpm"});
  const MethodOptions& o = options_for(options, "gpm");
  const std::string family = o.get_choice("weight", "2", {"1", "2", "3"});
  const std::string volume = o.get_choice("volume", "lattice", {"lattice", "shepard", "uniform", "voronoi", "vrsph"});
  o.reject_unused("gpm");
  check<ConfigError>(std::isfinite(a.h_factor) && a.h_factor > 0, "--h-factor must be positive, got ", a.h_factor);
  PointCloud cloud;
  Real dx = 0;
  if (!a.cloud_file.empty()) {
    for (const char* opt : {"--cloud", "--n", "--seed", "--delta", "--regular-layer"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply with --cloud-file");
    cloud = read_cloud_file(a.cloud_file, a.dim_opt->count() ? a.dim : 0).cloud;
    dx = estimate_spacing(cloud);
  } else {
    const auto ns = parse_int_list(a.n, "--n");
    check<ConfigError>(ns.size() == 1 || cmd.count("--n") == 0, "--at takes one --n (one cloud), got '", a.n, "'");
    CloudSpec spec;
    spec.family = parse_cloud_family(a.cloud);
    spec.box = Domain::unit_box(a.dim);
    spec.n = cmd.count("--n") ? ns[0] : 32;
    spec.delta = a.delta;
    spec.seed = a.seed;
    spec.regular_layer = a.regular_layer;
    const Real spacing = 1.0 / spec.n;
    if (spec.family != CloudFamily::Disk) spec.ghost_width = ghost_layers_for(a.h_factor * spacing, spacing) * spacing;
    const StudyCloud sc = make_study_cloud(spec);
    cloud = sc.cloud;
    dx = sc.dx;
  }
  const Real h = a.h_factor * dx;
  const std::vector<Vec3> points = read_points_csv(a.at, cloud.dim);
  const auto u = make_function_or_expression(a.u.empty() ? "cos-pi" : a.u, cloud.dim);
  SearchParams sp;
  sp.radius = h;
  sp.min_neighbours = 0;
  const NeighbourList nl = find_neighbours(cloud, sp);
  const std::vector<Real> V = gpm_volumes({cloud, nl, KernelType::CubicSpline, dx}, volume, family);
  std::vector<Real> up(cloud.positions.size()), ux(points.size());
  for (std::size_t i = 0; i < up.size(); ++i) up[i] = u->value(cloud.positions[i]);
  for (std::size_t q = 0; q < points.size(); ++q) ux[q] = u->value(points[q]);
  const GpmPointValues r = gpm_at_points(cloud, V, family, h, points, up, ux);
  Table t;
  t.columns = {"point", "x", "y", "z", "neighbours", "value", "value_exact", "value_error", "gradient_error",
               "laplacian", "laplacian_exact", "laplacian_error"};
  for (int k = 0; k < cloud.dim; ++k) t.columns.push_back(std::string("gradient_") + "xyz"[k]);
  for (std::size_t q = 0; q < points.size(); ++q) {
    const auto e = static_cast<Eigen::Index>(q);
    const Vec3 g = u->gradient(points[q]);
    Real gerr = 0;
    for (int k = 0; k < cloud.dim; ++k) gerr += std::pow(r.gradient(e, k) - g[k], 2);
    const Real lap = u->laplacian(points[q]);
    std::vector<std::pair<std::string, TableCell>> row{
        {"point", static_cast<long long>(q)}, {"x", points[q][0]}, {"y", points[q][1]}, {"z", points[q][2]},
        {"neighbours", static_cast<long long>(r.neighbours[q])}, {"value", r.value[e]}, {"value_exact", ux[q]},
        {"value_error", std::abs(r.value[e] - ux[q])}, {"gradient_error", std::sqrt(gerr)}, {"laplacian", r.laplacian[e]},
        {"laplacian_exact", lap}, {"laplacian_error", std::abs(r.laplacian[e] - lap)}};
    for (int k = 0; k < cloud.dim; ++k) row.emplace_back(std::string("gradient_") + "xyz"[k], r.gradient(e, k));
    t.add_row(row);
  }
  emit(t, a.out, Json::object({{"evaluation", "gpm at points"}, {"reference", "[IM] (2)-(4)"}}), "", "", "", "");
}

// `vrsph operator --problem im-table1`: [IM] Table 1 / Fig. 5 (reproduce/im_table1.hpp).
void operator_im_table1(const OperatorArgs& a, const CLI::App& cmd) {
  for (const char* opt : {"--cloud", "--n", "--h-factor", "--h-mode", "--h-knn", "--delta", "--kernel", "--regular-layer",
                          "--no-ghosts", "--u", "--exact", "--a", "--operator", "--method-opt", "--cloud-file"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply to --problem im-table1 (its cloud, h rule, function and "
                       "operators are [IM] §5.4's; choose --weight, --m, --levels, --points, --seed, --dim)");
  check<ConfigError>(a.methods == "gpm" || cmd.count("--method") == 0, "--problem im-table1 evaluates --method gpm only, got '",
                     a.methods, "'");
  ImTable1Options o;
  o.dim = a.dim_opt->count() ? a.dim : 2;
  o.weights = parse_name_list(a.im_weights, "--weight");
  o.m = parse_int_list(a.im_m, "--m");
  o.levels = parse_int_list(a.im_levels, "--levels");
  check<ConfigError>(a.im_points >= 1, "--points must be >= 1, got ", a.im_points);
  o.max_points = static_cast<Index>(a.im_points);
  o.volumes = parse_im_volumes(a.im_volumes, "--volumes");
  o.seed = a.seed;
  Progress progress;
  o.progress = [&progress](const std::string& label, double f) { progress.update(label, f); };
  const auto rows = im_table1(o);
  Table t;
  t.columns = {"series", "weight", "m", "level", "dx", "h", "particles", "in_omega", "evaluated", "neighbours_mean",
               "error_rel", "order", "order_fit", "theoretical_order", "volume_bias", "error_integral", "seconds"};
  for (const auto& r : rows) {
    auto nan_to_empty = [](Real v) -> TableCell { return std::isfinite(v) ? TableCell{v} : TableCell{std::monostate{}}; };
    t.add_row({{"series", r.weight + " m=" + std::to_string(r.m)}, {"weight", r.weight}, {"m", static_cast<long long>(r.m)},
               {"level", static_cast<long long>(r.level)}, {"dx", r.dx}, {"h", r.h},
               {"particles", static_cast<long long>(r.particles)}, {"in_omega", static_cast<long long>(r.in_omega)},
               {"evaluated", static_cast<long long>(r.evaluated)}, {"neighbours_mean", r.neighbours_mean},
               {"error_rel", r.error_rel}, {"order", nan_to_empty(r.order)}, {"order_fit", nan_to_empty(r.order_fit)},
               {"theoretical_order", nan_to_empty(im_theoretical_order(r.weight, r.m))}, {"volume_bias", r.volume_bias},
               {"error_integral", r.error_integral}, {"seconds", r.seconds}});
  }
  emit(t, a.out,
       Json::object({{"problem", "im-table1"},
                     {"reference", "[IM] Table 1 (Imoto, JJIAM 37 (2020), doi:10.1007/s13160-020-00407-1)"}}),
       "h", "error_rel",
       "series", "[IM] Table 1: relative max-norm error against h");
}
void add_operator_options(CLI::App* cmd, OperatorArgs& a) {
  cmd->add_option("--problem", a.problem,
                  "qw-trunc ([QW] Ex. 1,2,4 on [-1,1]^d), im-table1 ([IM] Table 1, gpm weights; see --weight), unit-box ([0,1]^d), aar-derivative ([AAR] e^x on [0,1], "
                  "all particles) or spe-patch ([SPE] §4 operator tests along a cross-section, see --test)")
      ->capture_default_str();
  a.dim_opt = cmd->add_option("--dim", a.dim, "Dimension 1, 2 or 3 (aar-derivative: 1)")->capture_default_str();
  cmd->add_option("--method", a.methods, "Comma-separated method names (see `vrsph methods`)")->capture_default_str();
  cmd->add_option("--method-opt", a.method_opts, "Method option key=value, or method:key=value for one method (repeatable)");
  cmd->add_option("--operator", a.op, "value, dx, dy, dz, gradient, laplacian, div-a-grad, hessian (rows exact on cubics, the same for every "
                  "method), first-derivative, second-derivative; on a vector field --u \"u_x,u_y[,u_z]\": divergence, curl, "
                  "vector-laplacian, grad-div (from the hessian rows), grad-div-composed (the method's gradient rows twice)")
      ->capture_default_str();
  cmd->add_option("--cloud", a.cloud, "Cloud family: uniform, perturbed, centroids, disk")->capture_default_str();
  cmd->add_option("--n", a.n, "Refinement list: intervals per direction, dx = side/n")->capture_default_str();
  cmd->add_option("--seed", a.seed, "Random seed (perturbed, centroids)")->check(seed_validator())->capture_default_str();
  a.h_factor_opt = cmd->add_option("--h-factor", a.h_factor, "Support radius h = h_factor * dx (aar-derivative: 6)")
                        ->capture_default_str();
  cmd->add_option("--h-mode", a.h_mode, "Support radius rule: fixed (kappa dx), covering (kappa max(dx, r_N)), knn (per particle)")
      ->capture_default_str();
  a.h_knn_opt = cmd->add_option("--h-knn", a.h_knn, "k for --h-mode knn: h_i = kappa * distance to the k-th neighbour (0: 2d)")
      ->capture_default_str();
  a.delta_opt = cmd->add_option("--delta", a.delta, "Perturbation amplitude in units of dx (aar-derivative: 0.25)")
                     ->capture_default_str();
  a.kernel_opt = cmd->add_option("--kernel", a.kernel, "Kernel: cubic, cubic-spe, gaussian, quintic, wendland-c2, wendland-c4 "
                                                         "(aar-derivative: gaussian)")
                      ->capture_default_str();
  cmd->add_option("--regular-layer", a.regular_layer,
                  "Perturbed clouds: particles within this many dx of a face move only tangentially")
      ->capture_default_str();
  a.ghosts_opt = cmd->add_flag("--no-ghosts", a.no_ghosts,
                                "No ghost particles: layout A with boundary particles ([QW] Example 4; implied by aar-derivative)");
  cmd->add_option("--periodic", a.periodic, "Comma-separated periodic axes x,y,z or all of the problem's box: no "
                  "boundary or ghost particles along them, every row sees across the faces");
  cmd->add_option("--u", a.u, "Test function: catalogue name (cos-pi, sin-pi, exp-x, ...) or expression in x,y,z; default cos-pi");
  cmd->add_option("--exact", a.exact, "Expected operator value as expression(s), components separated by ';' or by the commas outside parentheses (as in --u); default: exact derivatives of --u");
  cmd->add_option("--a", a.a, "Coefficient a(x) for div-a-grad: name or expression; default one-plus-r2");
  cmd->add_option("--format", a.out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a.out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a.out.plot, "Also plot error_inf against dx (log-log) into this PNG file");
  cmd->add_option("--cloud-file", a.cloud_file,
                  "Evaluate the operator on this cloud file (CSV x,y,z,tag,..., VTU/VTP, or Gmsh .msh) against the exact derivatives of --u: "
                  "error over interior particles, and over the tagged boundary particles apart");
  add_spe_patch_options(cmd, a.patch);
  cmd->add_option("--at", a.at, "Evaluate gpm's interpolant, gradient and Laplacian ([IM] (2)-(4)) at the points of this "
                  "CSV file (columns x[,y[,z]]) against the exact derivatives of --u; particles from --cloud/--n (one "
                  "value) on the unit box with ghost layers, or --cloud-file");
  cmd->add_option("--weight", a.im_weights, "im-table1: [IM] weights pi1-3, grad1-3, delta1-3")->capture_default_str();
  cmd->add_option("--m", a.im_m, "im-table1: regularity orders m of the h rule h = 2.6 * 2^(5/m-5) dx^(1/m)")->capture_default_str();
  cmd->add_option("--levels", a.im_levels, "im-table1: dx = 2^-level")->capture_default_str();
  cmd->add_option("--points", a.im_points, "im-table1: evaluation points per level (a seeded random subset of the "
                  "particles in Omega when there are more)")->capture_default_str();
  cmd->add_option("--volumes", a.im_volumes, "im-table1: particle volumes uniform (|Omega_H| / N, [IM] 5.4) or cells "
                  "(the lattice cells stretched to the boundary of Omega_H: dx^d inside, a control without the "
                  "volume bias)")->capture_default_str();
}

// The refinement study of a built-in problem (qw-trunc, unit-box, aar-derivative).
void operator_study(const OperatorArgs& a) {
  OperatorStudyParams p;
  p.problem = a.problem;
  const ProblemDefaults def = problem_defaults(p.problem);
  p.dim = a.dim_opt->count() ? a.dim : def.dim;
  p.methods = parse_name_list(a.methods, "--method");
  p.method_options = parse_method_options(a.method_opts, p.methods);
  note_row_forms(p.methods, p.method_options, StencilUse::Values);
  if (const auto v = parse_vector_operator(a.op)) {  // made from the gradient or Laplacian rows
    p.vector_op = v;
    p.op = base_operator(*v);
    check<ConfigError>(!a.u.empty(), "--operator ", a.op, " needs the vector field --u as ", p.dim,
                       " comma-separated components");
  } else {
    p.op = parse_operator(a.op);
  }
  p.cloud = parse_cloud_family(a.cloud);
  p.n = parse_int_list(a.n, "--n");
  p.seed = a.seed;
  p.h_factor = a.h_factor_opt->count() ? a.h_factor : def.h_factor;
  p.h_mode = parse_smoothing_mode(a.h_mode);
  p.h_knn = a.h_knn;
  check_h_knn_applies(a.h_knn_opt, a.h_mode);
  p.delta = a.delta_opt->count() ? a.delta : def.delta;
  p.ghosts = a.ghosts_opt->count() ? !a.no_ghosts : def.ghosts;
  p.regular_layer = a.regular_layer;
  p.kernel = a.kernel_opt->count() ? parse_kernel(a.kernel) : def.kernel;
  p.u = a.u;
  p.exact = a.exact;
  p.a = a.a;
  p.periodic = a.periodic;
  Progress progress;
  p.progress = [&progress](const std::string& label, double f) { progress.update(label, f); };
  const OperatorStudyResult r = run_operator_study(p);
  emit(to_table(r), a.out, metadata_json(r), "dx", "error_inf", "method",
       a.problem + " " + a.op + " " + a.cloud + " " + std::to_string(p.dim) + "D");
}

// Which mode the options ask for; each refuses the options of the others.
void run_operator(OperatorArgs& a, const CLI::App& cmd) {
  validate_output(a.out);
  check<ConfigError>(a.periodic.empty() || (a.at.empty() && a.problem != "im-table1" && a.problem != "spe-patch"),
                     "--periodic applies to the refinement study of --problem qw-trunc, unit-box or aar-derivative");
  if (!a.at.empty()) return operator_at_points(a, cmd);
  if (a.problem == "im-table1") return operator_im_table1(a, cmd);
  for (const char* opt : {"--weight", "--m", "--levels", "--points", "--volumes"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " applies to --problem im-table1 only");
  if (a.problem == "spe-patch") {
    check<ConfigError>(a.cloud_file.empty(), "--cloud-file does not apply to --problem spe-patch");
    return run_spe_patch_command(a.patch, cmd, a.dim, a.h_factor, a.delta, a.seed, a.out);
  }
  for (const char* opt : {"--test", "--exponent", "--rotated", "--variant", "--profile"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " applies to --problem spe-patch only");
  check<ConfigError>(a.cloud_file.empty() || a.periodic.empty(), "--periodic applies to the generated clouds, not to "
                     "--cloud-file");
  if (!a.cloud_file.empty()) return operator_on_cloud_file(a, cmd);
  operator_study(a);
}
}  // namespace

void add_operator_command(CLI::App& app) {
  auto a = std::make_shared<OperatorArgs>();
  auto* cmd = app.add_subcommand("operator", "Truncation-error study: method x operator x cloud x refinement list");
  add_operator_options(cmd, *a);
  cmd->callback([a, cmd] { run_operator(*a, *cmd); });
}

}  // namespace vrsph::cli
