// SPDX-License-Identifier: BSD-3-Clause
// `vrsph solve --cloud-file` and `vrsph study --cloud-file-pattern`: boundary value
// problems on the user's own clouds (CSV with tags and normals), data from expressions
// evaluated at the file's points, each solve one library call (problem/).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/parallel/distributed_cloud.hpp>
#include <vrsph/problem/from_expressions.hpp>
#include <vrsph/solve/solver.hpp>
#include "../geometry_args.hpp"
#include "study_args.hpp"

namespace vrsph::cli {

namespace {
// The cloud comes from the file or geometry: the generators' options would be silently ignored
// (a geometry's fill uses --seed and --delta).
void reject_generator_options(const CLI::App& cmd, const char* source, bool geometry = false) {
  for (const char* opt : {"--cloud", "--problem", "--seed", "--delta", "--perturb-boundary", "--regular-layer",
                          "--neumann", "--robin", "--beta", "--periodic"}) {
    if (geometry && (std::string(opt) == "--seed" || std::string(opt) == "--delta")) continue;
    if (!geometry && std::string(opt) == "--periodic") continue;  // a file's box may wrap (--box)
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply with ", source,
                       geometry ? " (the geometry is the domain; --neumann-where tags its boundary)"
                                : " (the cloud, its tags and normals come from the file)");
  }
  if (!geometry)
    for (const char* opt : {"--spacing", "--fill", "--neumann-where", "--dirichlet-where"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " needs --geometry");
  check<ConfigError>(cmd.count("--box") == 0 || cmd.count("--periodic") > 0, "--box needs --periodic (it is the box "
                     "whose faces wrap; a cloud file's domain is otherwise its particles)");
}

// --box "x0,y0[,z0],x1,y1[,z1]" (default the unit box) periodic along --periodic: the file's
// particles must lie in [lo, hi) along those axes, as a generated periodic cloud's do.
Domain periodic_file_box(const std::string& box, const std::string& axes, int dim) {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (int k = 0; k < dim; ++k) hi[k] = 1;
  if (!box.empty()) {
    const std::vector<double> v = parse_real_list(box, "--box");
    check<ConfigError>(v.size() == static_cast<std::size_t>(2 * dim), "--box takes ", 2 * dim, " numbers for a ", dim,
                       "D cloud (lower corner, then upper corner), got ", v.size());
    for (int k = 0; k < dim; ++k) {
      lo[k] = v[static_cast<std::size_t>(k)];
      hi[k] = v[static_cast<std::size_t>(dim + k)];
    }
  }
  try {
    return Domain::periodic_box(dim, lo, hi, axes);
  } catch (const InputError& e) {  // the box is an option's: a configuration error
    throw ConfigError(detail::concat("--box: ", e.what()));
  }
}

// This rank's part of the cloud of one run: the file (read in parallel under mpirun, see
// read_cloud_file_part), or the geometry filled at `spacing` (a lattice fill makes only
// this rank's layers, and rank 0 the boundary; a blue-noise fill, which grows from the whole
// boundary, is made whole on every rank, which keeps its slice).
CloudFilePart load_cloud(const StudyArgs& a, const CloudFileArgs& file, const std::string& path, double spacing,
                         const CLI::App& cmd, const Communicator& comm) {
  if (file.geometry.empty()) {
    CloudFilePart part = read_cloud_file_part(path, a.dim_opt->count() ? a.dim : 0, comm);
    if (!a.periodic.empty()) {
      const int dim = static_cast<int>(max_over_ranks(comm, static_cast<double>(part.file.cloud.size() ? part.file.cloud.dim : 0)));
      collective(comm, [&] { part.file.cloud.domain = periodic_file_box(file.box, a.periodic, dim); });
    }
    return part;
  }
  GeometryRequest r;
  r.path = file.geometry;
  r.spacing = spacing;
  r.fill = file.fill;
  if (cmd.count("--delta")) r.delta = a.delta;
  r.seed = a.seed;
  r.neumann_where = file.neumann_where;
  r.dirichlet_where = file.dirichlet_where;
  const bool in_parts = file.fill != "blue-noise";
  if (in_parts) {
    r.part = comm.rank();
    r.parts = comm.size();
  }
  CloudFilePart part;
  part.file.source = path;
  collective(comm, [&] {
    part.file.cloud = make_geometry_cloud(r).cloud;
    check<InputError>(!a.dim_opt->count() || a.dim == part.file.cloud.dim, "--dim ", a.dim, " does not match the ",
                      part.file.cloud.dim, "D geometry ", file.geometry);
  });
  const auto mine = static_cast<long long>(part.file.cloud.size());
  if (in_parts) {
    part.total = static_cast<Index>(sum_over_ranks(comm, mine));
    part.first = static_cast<Index>(offset_over_ranks(comm, mine));
  } else {
    part.total = static_cast<Index>(mine);
    part.first = static_cast<Index>(mine * comm.rank() / comm.size());
    part.file.cloud = slice(part.file.cloud, part.first, static_cast<Index>(mine * (comm.rank() + 1) / comm.size()));
  }
  return part;
}

// The label of a geometry run, e.g. "torus.stl@0.05".
std::string geometry_label(const std::string& geometry, double spacing) {
  std::ostringstream s;
  s << geometry << '@' << spacing;
  return s.str();
}

BvpSolveOptions solve_options(const StudyArgs& a, const std::string& method, const MethodOptions& method_options,
                              double h) {
  check<ConfigError>(std::isfinite(h) && h >= 0, "--h must be >= 0, got ", h);
  BvpSolveOptions o;
  o.method = method;
  o.method_options = method_options;
  o.kernel = parse_kernel(a.kernel);
  o.h = h;
  o.h_factor = a.h_factor;
  o.h_mode = parse_smoothing_mode(a.h_mode);
  o.h_knn = a.h_knn;
  check_h_knn_applies(a.h_knn_opt, a.h_mode);
  o.solver = solver_options(a);
  o.on_infeasible = parse_infeasible_policy(a.on_infeasible);
  o.infeasible_tolerance = a.infeasible_tol;
  return o;
}

struct FileRun {
  ExpressionProblem ep;
  BvpSolution s;
  ErrorReport errors;  // only with an exact solution
  double seconds = 0;
};

FileRun run_on_file(const StudyArgs& a, const CloudFileArgs& file, const std::string& path, const std::string& method,
                    const MethodOptions& method_options, double h, double spacing, const CLI::App& cmd) {
  Stopwatch watch;
  FileRun r;
  // Under mpirun each rank holds only its part of the particles (the file's order) and the
  // solve is distributed; sizes, errors and diagnostics are the whole cloud's.
  const Communicator& comm = communicator();
  fault_point(comm, "read");  // outside any collective: the MPI tests' abort path
  CloudFilePart part = load_cloud(a, file, path, spacing, cmd, comm);
  const CloudFile& cf = part.file;
  const auto column = [&](const std::string& name, const char* option) {
    return name.empty() ? nullptr : &cf.field(name, option);
  };
  ProblemValues values;
  std::vector<Real> volumes;
  ProblemExpressions expressions{a.u, a.a, a.f, a.g, a.q};
  // Every rank steps finite differences of the expressions by the whole cloud's length.
  if (comm.distributed()) expressions.length_scale = length_scale(cf.cloud, comm);
  collective(comm, [&] {
    try {
      fault_point(comm, "problem");
      values = {column(file.u_column, "--u-column"), column(file.a_column, "--a-column"),
                column(file.f_column, "--f-column"), column(file.g_column, "--g-column"),
                column(file.q_column, "--q-column")};
      if (!file.volume_column.empty()) {
        const Field& v = cf.field(file.volume_column, "--volume-column");
        for (Index i = 0; i < v.size(); ++i)
          check<InputError>(v[i] > 0, path, ": --volume-column '", file.volume_column, "' is not positive (", v[i],
                            ") at particle ", i);
        volumes.assign(v.data(), v.data() + v.size());
      }
      if (!a.mobility.empty()) expressions.mobility = parse_expression_list(a.mobility, "--mobility");
      r.ep = problem_from_expressions(cf.cloud, expressions, values);
    } catch (const std::exception& e) {  // particles named by their place in the file
      if (part.first == 0) throw;
      rethrow_with_message(e, renumber_particles(e.what(), [&](long long i) { return i + part.first; }));
    }
  });
  r.ep.problem.fix_constant = a.fix_constant;
  BvpSolveOptions o = solve_options(a, method, method_options, h);
  o.label = method + " on " + path;
  if (comm.distributed()) o.communicator = comm;
  r.s = solve(r.ep.problem, o);
  print_warnings(r.s.warnings);
  print_infeasible_rows(o.label, comm.distributed() ? PointCloud{} : r.ep.problem.cloud, r.s.infeasible_particles,
                        r.s.infeasible_residuals);
  if (any_rank(comm, r.ep.exact.size() > 0)) {
    const PointCloud& c = r.ep.problem.cloud;
    Eigen::MatrixXd err(c.size(), 1);
    err.col(0) = r.s.u - r.ep.exact;
    remove_periodic_constant(err, c, comm);  // a fully periodic box (--periodic): u up to a constant
    // L2 weights: the file's volumes, else the estimated spacing to the power d.
    if (volumes.empty()) volumes.assign(static_cast<std::size_t>(c.size()), std::pow(r.s.spacing, c.dim));
    // Near the boundary: within one support radius of the nearest tagged boundary particle
    // (of every rank's part).
    r.errors = error_norms_over_ranks(err, unknown_mask(c), c, r.s.h, volumes, comm, part.first);
  }
  r.seconds = watch.seconds();
  return r;
}

// x,y,z,tag,u[,local_residual][,u_exact,error][,nx,ny,nz] with 17 significant digits (the
// normals, when the cloud has them, let the field plot tell the domain from its holes).
void write_fields(const std::string& path, const PointCloud& c, const Field& u, const Field* local_residual,
                  const Field* exact, bool normals = false) {
  normals = normals && c.has_normals();
  write_file(path, "CSV field file", [&](std::ostream& out) {
    out.precision(17);
    out << "x,y,z,tag,u" << (local_residual ? ",local_residual" : "") << (exact ? ",u_exact,error" : "")
        << (normals ? ",nx,ny,nz" : "") << '\n';
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& x = c.positions[static_cast<std::size_t>(i)];
      out << x[0] << ',' << x[1] << ',' << x[2] << ',' << to_string(c.tags[static_cast<std::size_t>(i)]) << ',' << u[i];
      if (local_residual) out << ',' << (*local_residual)[i];
      if (exact) out << ',' << (*exact)[i] << ',' << u[i] - (*exact)[i];
      if (normals) {
        const Vec3& nv = c.normals[static_cast<std::size_t>(i)];
        out << ',' << nv[0] << ',' << nv[1] << ',' << nv[2];
      }
      out << '\n';
    }
  });
}

void write_field_csv(const std::string& path, const FileRun& r) {
  write_fields(path, r.ep.problem.cloud, r.s.u, &r.s.local_residual, r.ep.exact.size() ? &r.ep.exact : nullptr);
}

// One row: sizes, diagnostics, and errors only when an exact solution was given.
std::vector<std::pair<std::string, TableCell>> row_of(const std::string& method, const FileRun& r) {
  const BvpSolution& s = r.s;
  std::vector<std::pair<std::string, TableCell>> row{
      {"method", method}, {"particles", static_cast<long long>(s.particles)},
      {"unknowns", static_cast<long long>(s.unknowns)}, {"dim", static_cast<long long>(r.ep.problem.cloud.dim)},
      {"spacing", s.spacing}, {"h", s.h}, {"mmatrix", s.m_matrix}, {"infeasible", static_cast<long long>(s.infeasible)},
      {"condition_max", s.condition_max}, {"solver", s.solve.solver},
      {"solver_iterations", static_cast<long long>(s.solve.iterations)}, {"solver_residual", s.solve.residual},
      {"neumann_imbalance", s.neumann_imbalance}, {"seconds_total", r.seconds}};
  if (r.ep.exact.size()) {
    row.emplace_back("error_inf", r.errors.all.linf);
    row.emplace_back("error_l2", r.errors.all.l2);
    // Split at one support radius from the nearest tagged boundary particle.
    row.emplace_back("error_inf_interior", r.errors.interior.linf);
    row.emplace_back("error_inf_boundary", r.errors.near_boundary.linf);
  }
  return row;
}

const std::vector<std::string> base_columns = {
    "method", "particles", "unknowns", "dim", "spacing", "h", "mmatrix", "infeasible", "condition_max", "solver",
    "solver_iterations", "solver_residual", "neumann_imbalance"};
const std::vector<std::pair<const char*, const char*>> column_options = {
    {"--u-column", "the exact solution u"}, {"--a-column", "the coefficient a"}, {"--f-column", "the right-hand side f"},
    {"--g-column", "the Dirichlet data g"}, {"--q-column", "the Neumann data a du/dn"}};
}  // namespace

void plot_solution(const PointCloud& cloud, const Field& u, const Field* exact, const std::string& png,
                   const std::string& title) {
  const TemporaryFile csv("vrsph-fields", ".csv");
  write_fields(csv.path(), cloud, u, nullptr, exact, true);
  run_plot_script("plot_field.py", csv.path(), png,
                  " --dim " + std::to_string(cloud.dim) + " --title " + shell_quote(title));
}

VtuFormat parse_vtu_format(const std::string& s) {
  check<ConfigError>(s == "binary" || s == "ascii", "--vtu-format must be binary or ascii, got '", s, "'");
  return s == "ascii" ? VtuFormat::Ascii : VtuFormat::Binary;
}

void add_geometry_options(CLI::App* cmd, CloudFileArgs& file, bool study) {
  cmd->add_option("--geometry", file.geometry,
                  "Solve in this domain instead: a 2D GeoJSON polygon or a 3D closed surface (STL, OFF, OBJ), "
                  "filled at --spacing as `vrsph cloud --geometry` does (boundary Dirichlet, Neumann on surface regions named "
                  "\"...neumann...\" or where --neumann-where holds)");
  cmd->add_option("--spacing", file.spacing, study ? "With --geometry: comma-separated particle spacings (the refinement list)"
                                                   : "With --geometry: the particle spacing");
  cmd->add_option("--fill", file.fill, "With --geometry: interior particles uniform (lattice), perturbed (--delta, default "
                                       "0.3; --seed) or blue-noise (--seed)")->capture_default_str();
  cmd->add_option("--neumann-where", file.neumann_where,
                  "With --geometry: boundary particles where this expression is non-zero are Neumann (e.g. \"z > 0.99\")");
  cmd->add_option("--dirichlet-where", file.dirichlet_where,
                  "With --geometry: only boundary particles where this expression is non-zero are Dirichlet, the rest Neumann");
  cmd->add_option("--box", file.box,
                  "With a cloud file and --periodic: the box x0,y0[,z0],x1,y1[,z1] whose faces wrap along the periodic "
                  "axes (default the unit box; particles must lie in [lo, hi) along them)");
}

void add_column_options(CLI::App* cmd, CloudFileArgs& file, const std::string& file_option) {
  std::string* targets[] = {&file.u_column, &file.a_column, &file.f_column, &file.g_column, &file.q_column};
  for (std::size_t k = 0; k < column_options.size(); ++k)
    cmd->add_option(column_options[k].first, *targets[k],
                    std::string("With ") + file_option + ": take " + column_options[k].second +
                        " from this extra column of the file (instead of an expression)");
  cmd->add_option("--volume-column", file.volume_column,
                  "With " + file_option + ": particle volumes from this column, the weights of the L2 error "
                  "(default: spacing^d)");
}

void reject_column_options(const CLI::App& cmd, const std::string& file_option) {
  for (const auto& [opt, what] : column_options)
    check<ConfigError>(cmd.count(opt) == 0, opt, " needs ", file_option, " (", what, " from a column of the cloud file)");
  check<ConfigError>(cmd.count("--volume-column") == 0, "--volume-column needs ", file_option);
  // (It was ignored without a cloud file: a generated cloud's support is --h-factor x dx.)
  check<ConfigError>(cmd.count("--h") == 0, "--h needs ", file_option, " or --geometry (a generated cloud's support "
                     "radius is --h-factor x its spacing)");
}

void solve_cloud_file(const StudyArgs& a, const CloudFileArgs& file, const CLI::App& cmd) {
  const bool geometry = !file.geometry.empty();
  const char* source = geometry ? "--geometry" : "--cloud-file";
  check<ConfigError>(!geometry || file.path.empty(), "give --cloud-file or --geometry, not both");
  reject_generator_options(cmd, source, geometry);
  check<ConfigError>(cmd.count("--n") == 0, "--n does not apply with ", source,
                     geometry ? " (--spacing sets the resolution)" : " (the cloud comes from the file)");
  double spacing = 0;
  if (geometry) {
    check<ConfigError>(!file.spacing.empty(), "--geometry needs --spacing (the particle distance)");
    const auto s = parse_real(file.spacing);
    check<ConfigError>(s.has_value(), "--spacing of vrsph solve is one number, got '", file.spacing, "'");
    spacing = *s;
  }
  check<ConfigError>(!communicator().distributed() || (file.csv.empty() && a.out.plot.empty()),
                     "--csv and --plot write the whole field on one rank: not available under mpirun (the .pvtu "
                     "pieces hold the fields)");
  const std::string label = geometry ? geometry_label(file.geometry, spacing) : file.path;
  const auto methods = parse_name_list(a.methods, "--method");
  check<ConfigError>(methods.size() == 1, "vrsph solve takes exactly one --method");
  const auto options = parse_method_options(a.method_opts, methods);
  const FileRun r = run_on_file(a, file, label, methods.front(), options_for(options, methods.front()), file.h, spacing, cmd);
  const bool exact = r.ep.exact.size() > 0;
  std::vector<PointField> fields{{"U", r.s.u}, {"local_residual", r.s.local_residual}};
  if (exact) {
    fields.push_back({"u_exact", r.ep.exact});
    fields.push_back({"error", r.s.u - r.ep.exact});
  }
  fault_point(communicator(), "output");  // outside any collective: the MPI tests' abort path
  if (a.vtu.empty()) {
  } else if (communicator().distributed()) {
    collective(communicator(), [&] {
      write_pvtu_piece(pvtu_path(a.vtu), communicator().rank(), communicator().size(), r.ep.problem.cloud, fields,
                       parse_vtu_format(a.vtu_format));
    });
  } else {
    write_vtu(a.vtu, r.ep.problem.cloud, fields, parse_vtu_format(a.vtu_format));
  }
  if (!file.csv.empty()) write_field_csv(file.csv, r);
  if (!a.out.plot.empty())
    plot_solution(r.ep.problem.cloud, r.s.u, exact ? &r.ep.exact : nullptr, a.out.plot, methods.front() + " on " + label);
  Table t;
  t.columns = base_columns;
  if (exact) t.columns.insert(t.columns.end(), {"error_inf", "error_l2", "error_inf_interior", "error_inf_boundary"});
  t.columns.insert(t.columns.end(), {"seconds_total", "vtu"});
  auto row = row_of(methods.front(), r);
  row.emplace_back("vtu", communicator().distributed() && !a.vtu.empty() ? pvtu_path(a.vtu) : a.vtu);
  t.add_row(row);
  std::cout << solve_summary(t, a.out.format, r.s.warnings, r.s.infeasible_particles);
}

void study_cloud_files(const StudyArgs& a, const CloudFileArgs& file, const CLI::App& cmd) {
  const bool geometry = !file.geometry.empty();
  check<ConfigError>(!geometry || file.pattern.empty(), "give --cloud-file-pattern or --geometry, not both");
  reject_generator_options(cmd, geometry ? "--geometry" : "--cloud-file-pattern", geometry);
  check<ConfigError>(geometry || file.pattern.find("{n}") != std::string::npos, "--cloud-file-pattern '", file.pattern,
                     "' must contain {n}, replaced by each value of --n (e.g. cloud_{n}.csv)");
  check<ConfigError>(!a.u.empty() || !file.u_column.empty(), "a convergence study needs the exact solution --u (or --u-column)");
  const auto methods = parse_name_list(a.methods, "--method");
  // Levels: the --n list for files; for a geometry the --spacing list (n = 1, 2, ... in the rows).
  std::vector<int> levels;
  std::vector<double> spacings;
  if (geometry) {
    check<ConfigError>(cmd.count("--n") == 0, "--n does not apply with --geometry (--spacing lists the resolutions)");
    check<ConfigError>(!file.spacing.empty(), "--geometry needs --spacing (a comma-separated list of particle distances)");
    spacings = parse_real_list(file.spacing, "--spacing");
    for (std::size_t k = 0; k < spacings.size(); ++k) levels.push_back(static_cast<int>(k) + 1);
  } else {
    levels = parse_int_list(a.n, "--n");
  }
  const auto options = parse_method_options(a.method_opts, methods);
  Table t;
  t.columns = {"n", "file"};
  t.columns.insert(t.columns.end(), base_columns.begin(), base_columns.end());
  t.columns.insert(t.columns.end(), {"error_inf", "order_inf", "error_l2", "order_l2", "error_inf_interior",
                                     "error_inf_boundary", "seconds_total"});
  Json fitted = Json::object();
  Progress progress;
  double done = 0;
  for (const auto& m : methods) {
    std::vector<Real> sizes, einf, el2;
    for (std::size_t level = 0; level < levels.size(); ++level) {
      const int n = levels[level];
      std::string path = file.pattern;
      if (geometry) path = geometry_label(file.geometry, spacings[level]);
      else path.replace(path.find("{n}"), 3, std::to_string(n));
      progress.update(m + " " + path, done / static_cast<double>(methods.size() * levels.size()));
      const FileRun r = run_on_file(a, file, path, m, options_for(options, m), file.h, geometry ? spacings[level] : 0, cmd);
      sizes.push_back(r.s.spacing);
      einf.push_back(r.errors.all.linf);
      el2.push_back(r.errors.all.l2);
      auto row = row_of(m, r);
      row.emplace_back("n", static_cast<long long>(n));
      row.emplace_back("file", path);
      const auto k = sizes.size();
      if (k > 1) {  // observed order against the estimated spacing of each file
        const Real ratio = std::log(sizes[k - 2] / sizes[k - 1]);
        row.emplace_back("order_inf", std::log(einf[k - 2] / einf[k - 1]) / ratio);
        row.emplace_back("order_l2", std::log(el2[k - 2] / el2[k - 1]) / ratio);
      }
      t.add_row(row);
      done += 1;
    }
    if (sizes.size() > 1) fitted[m] = least_squares_order(sizes, einf);
  }
  Json meta;
  if (geometry) {
    meta["geometry"] = file.geometry;
    meta["fill"] = file.fill;
  } else {
    meta["cloud_file_pattern"] = file.pattern;
  }
  meta["fitted_order_inf"] = fitted;
  meta["u"] = a.u;
  emit(t, a.out, meta, "spacing", "error_inf", "method", geometry ? file.geometry : "cloud files " + file.pattern);
}

}  // namespace vrsph::cli
