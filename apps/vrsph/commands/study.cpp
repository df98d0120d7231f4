// SPDX-License-Identifier: BSD-3-Clause
// `vrsph study` (convergence of a boundary value problem over a refinement list) and
// `vrsph solve` (one problem, fields to VTU).
#include <iostream>
#include <vrsph/io/json.hpp>
#include <vrsph/reproduce/published_problems.hpp>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/reproduce/heterogeneous_study.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/vtu.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#include "../problem_file.hpp"
#include "../gathered_fields.hpp"
#include "../relaunch.hpp"
#include "heterogeneous_args.hpp"
#include "study_args.hpp"

namespace vrsph::cli {

namespace {

void add_common(CLI::App* cmd, StudyArgs& a) {
  a.problem_opt = cmd->add_option("--problem", a.problem,
                  "qw-ex5 ([QW] Example 5), aar-static ([AAR] rod: -u'' = e^x, u(0) = 0, u'(1) = 0), spe-dirichlet / "
                  "spe-mixed ([SPE] §5 Laplace problems, relative error (95) in error_rel), spe-channel / spe-lognormal / spe10 "
                  "([SPE] §5.3 heterogeneous media against TPFA, see the group below) or custom "
                  "(with --u --a --f, or --mobility); --u implies custom")
      ->capture_default_str();
  a.dim_opt = cmd->add_option("--dim", a.dim, "Dimension 1, 2 or 3 (qw-ex5 in 3D: sin sin sin, a = 1 + |x|^2; aar-static: 1)")
                  ->capture_default_str();
  cmd->add_option("--method", a.methods, "Comma-separated method names (see `vrsph methods`)")->capture_default_str();
  cmd->add_option("--method-opt", a.method_opts, "Method option key=value, or method:key=value (repeatable)");
  cmd->add_option("--cloud", a.cloud, "uniform, perturbed, centroids or disk")->capture_default_str();
  cmd->add_option("--seed", a.seed, "Random seed (perturbed, centroids)")->check(seed_validator())->capture_default_str();
  a.h_factor_opt = cmd->add_option("--h-factor", a.h_factor, "Support radius h = h_factor * dx (default 3; aar-static: 6 = Gaussian with l = dx). For "
                       "spe-dirichlet/spe-mixed it is the paper's f = l/dx and the support is 2 f dx (default 1.001)")
                       ->capture_default_str();
  cmd->add_option("--h-mode", a.h_mode, "Support radius rule: fixed (kappa dx), covering (kappa max(dx, r_N)), knn (per particle)")
      ->capture_default_str();
  a.h_knn_opt = cmd->add_option("--h-knn", a.h_knn, "k for --h-mode knn: h_i = kappa * distance to the k-th neighbour (0: 2d)")
      ->capture_default_str();
  a.delta_opt = cmd->add_option("--delta", a.delta, "Perturbation amplitude in units of dx (default 0.5; aar-static: 0.25)")
                    ->capture_default_str();
  cmd->add_flag("--perturb-boundary", a.perturb_boundary, "Also move boundary particles along their faces");
  cmd->add_option("--regular-layer", a.regular_layer,
                  "Perturbed clouds: particles within this many dx of a face move only tangentially")
      ->capture_default_str();
  a.kernel_opt = cmd->add_option("--kernel", a.kernel, "Kernel: cubic, cubic-spe, gaussian, quintic, wendland-c2, wendland-c4 "
                                                        "(default cubic; aar-static: gaussian)")
                     ->capture_default_str();
  cmd->add_option("--periodic", a.periodic,
                  "Comma-separated periodic axes x,y,z or all: the unit box wraps around along them (no boundary "
                  "particles there; fully periodic: u with zero mean, errors up to the constant, f must have zero mean)");
  cmd->add_option("--neumann", a.neumann,
                  "Comma-separated Neumann faces x0,x1,y0,y1,z0,z1 or all (flux rows a du/dn = q from the method's own "
                  "gradient; default: the problem's, none for qw-ex5)");
  cmd->add_option("--q", a.q, "Neumann data a du/dn as an expression (default: from the exact solution u)");
  cmd->add_option("--robin", a.robin,
                  "Comma-separated Robin faces x0,x1,y0,y1,z0,z1 or all: flux rows a du/dn + beta u = q from the "
                  "method's own gradient (q default: from u); needs --beta");
  cmd->add_option("--beta", a.beta, "Robin coefficient beta(x,y,z) >= 0 (expression) on the --robin faces");
  cmd->add_flag("--fix-constant", a.fix_constant,
                "Pin the unknown nearest the centre to g (needed when every boundary face is Neumann)");
  cmd->add_option("--solver", a.solver,
                  "Linear solver: auto (direct when small, else petsc), petsc (GMRES + BoomerAMG by default), sparselu, "
                  "umfpack, bicgstab")
      ->capture_default_str();
  cmd->add_option("--petsc-options", a.petsc_options,
                  "PETSc options for --solver petsc/auto, e.g. \"-ksp_type cg -pc_type gamg\" (after the defaults and "
                  "PETSC_OPTIONS)");
  cmd->add_flag("--monitor", a.monitor, "Print the iterative solver's residual at every iteration (stderr)");
  cmd->add_option("--u", a.u, "Exact solution u(x,y,z): expression or catalogue name (custom problem)");
  cmd->add_option("--a", a.a, "Coefficient a(x,y,z) > 0 (custom problem; default 1)");
  cmd->add_option("--mobility", a.mobility,
                  "Diagonal tensor mobility M = diag(m1, .., md): comma-separated expressions > 0, one per direction, "
                  "instead of --a (custom problem: f = div(M grad u), Neumann q = n.M grad u; vrsph and the [SPE] schemes)");
  a.layout_opt = cmd->add_option("--layout", a.layout,
                                 "vertex (layout A: lattice vertices, default) or cells (layout B: cell centres plus "
                                 "boundary particles at face centres and corners; default of spe-*)");
  cmd->add_option("--f", a.f, "Right-hand side f = div(a grad u) (custom; default: computed from u and a)");
  cmd->add_option("--g", a.g, "Dirichlet data g (default: u)");
  cmd->add_option("--on-infeasible", a.on_infeasible, "Particles whose moment conditions cannot be met: warn or error")
      ->capture_default_str();
  cmd->add_option("--infeasible-tol", a.infeasible_tol, "Relative local residual above which a particle is infeasible")
      ->capture_default_str();
}

BvpStudyParams to_params(const StudyArgs& a, const std::vector<std::string>& methods) {
  BvpStudyParams p;
  p.catalogue = published_problems();  // aar-static, spe-dirichlet, spe-mixed
  // Any of --u/--a/--f implies a custom problem unless --problem says otherwise (then the
  // problem's own check names the conflict); a custom problem without --u says it needs u.
  const bool custom_data = !a.u.empty() || !a.a.empty() || !a.f.empty() || !a.mobility.empty();
  p.problem = (custom_data && !a.problem_opt->count()) ? "custom" : a.problem;
  const ProblemDefaults def = problem_defaults(p.problem);
  p.dim = a.dim_opt->count() ? a.dim : def.dim;
  p.methods = methods;
  p.method_options = parse_method_options(a.method_opts, methods);
  p.cloud = parse_cloud_family(a.cloud);
  p.h_factor = a.h_factor_opt->count() ? a.h_factor : def.h_factor;
  p.h_mode = parse_smoothing_mode(a.h_mode);
  p.h_knn = a.h_knn;
  check_h_knn_applies(a.h_knn_opt, a.h_mode);
  p.delta = a.delta_opt->count() ? a.delta : def.delta;
  p.perturb_boundary = a.perturb_boundary;
  p.regular_layer = a.regular_layer;
  p.kernel = a.kernel_opt->count() ? parse_kernel(a.kernel) : def.kernel;
  if (!a.neumann.empty()) p.neumann = parse_name_list(a.neumann, "--neumann");
  p.periodic = a.periodic;
  if (!a.robin.empty()) p.robin = parse_name_list(a.robin, "--robin");
  p.beta = a.beta;
  p.q = a.q;
  p.fix_constant = a.fix_constant;
  p.solver = solver_options(a);
  p.u = a.u;
  p.a = a.a;
  p.f = a.f;
  p.g = a.g;
  if (!a.mobility.empty()) p.mobility = parse_expression_list(a.mobility, "--mobility");
  if (a.layout_opt->count()) {
    check<ConfigError>(a.layout == "vertex" || a.layout == "cells", "--layout must be vertex or cells, got '", a.layout, "'");
    p.layout = a.layout == "cells" ? Layout::CellCentred : Layout::Vertex;
  } else {
    p.layout = def.cell_layout ? Layout::CellCentred : Layout::Vertex;
  }
  p.on_infeasible = parse_infeasible_policy(a.on_infeasible);
  p.infeasible_tolerance = a.infeasible_tol;
  p.seeds = {a.seed};
  return p;
}

// --ranks auto: a large run solved by PETSc goes to one rank per core (relaunch.hpp).
// The study's own checks first: a run this process would refuse is refused here, not on the ranks.
void run_study_on_ranks_if_large(const BvpStudyParams& p) {
  const StudySize size = checked_study_size(p);
  vrsph::cli::run_on_ranks_if_large(size.particles, p.dim, size.petsc);
}

}  // namespace

SolverOptions solver_options(const StudyArgs& a) {
  SolverOptions o;
  o.type = parse_solver(a.solver);
  o.petsc_options = a.petsc_options;
  if (!a.petsc_options.empty())
    check<ConfigError>(o.type == SolverType::Petsc || o.type == SolverType::Auto,
                       "--petsc-options applies to --solver petsc or auto, not ", a.solver);
  if (a.monitor)
    o.monitor = [](int it, Real r) { std::cerr << "  solver iteration " << it << ": residual " << r << '\n'; };
  return o;
}

// One line per kind of condition: the runs' infeasible-row warnings become one line (how many
// runs, the first run's count and worst row); other warnings once each.
void print_warnings(const std::vector<std::string>& warnings, bool listed) {
  std::vector<std::string> infeasible, other;
  for (const auto& w : warnings)
    if (w.find("could not meet their moment conditions") != std::string::npos) infeasible.push_back(w);
    else if (std::find(other.begin(), other.end(), w) == other.end()) other.push_back(w);
  const char* hint = listed && !verbose() ? "; --verbose lists them" : "";
  if (infeasible.size() == 1)
    std::cerr << "vrsph: warning: " << infeasible.front() << hint << '\n';
  else if (!infeasible.empty())
    std::cerr << "vrsph: warning: " << infeasible.size() << " runs had rows that could not meet their moment conditions; "
              << "first: " << infeasible.front() << hint << '\n';
  for (const auto& w : other) std::cerr << "vrsph: warning: " << w << '\n';
}

void print_infeasible_rows(const std::string& label, const PointCloud& cloud, const std::vector<Index>& particles,
                           const std::vector<Real>& residuals) {
  if (!verbose() || particles.empty()) return;
  std::cerr << "vrsph: " << label << ": " << particles.size() << " row(s) that could not meet their moment conditions "
            << "(particle, relative residual, position):\n";
  for (std::size_t k = 0; k < particles.size(); ++k) {
    std::cerr << "  " << particles[k] << ' ' << (k < residuals.size() ? residuals[k] : std::nan(""));
    const auto i = static_cast<std::size_t>(particles[k]);
    if (i < cloud.positions.size()) {
      const Vec3& x = cloud.positions[i];
      std::cerr << " (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
    }
    std::cerr << '\n';
  }
}

std::string solve_summary(Table t, const std::string& format, const std::vector<std::string>& warnings,
                          const std::vector<Index>& infeasible) {
  const TableFormat f = parse_table_format(format);
  // Tables: the number of warnings (they went to stderr); JSON: the warnings themselves and
  // every infeasible row in the one row of `solve`.
  if (f != TableFormat::Json) {
    t.columns.push_back("warnings");
    t.rows.front().push_back(static_cast<long long>(warnings.size()));
    return format_table(t, f);
  }
  Json j = Json::object();
  j["rows"] = json_rows(t);
  j["rows"].at(0)["warnings"] = warnings;
  j["rows"].at(0)["infeasible_particles"] = infeasible;
  return j.dump(2) + "\n";
}

void add_study_command(CLI::App& app) {
  auto a = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand("study", "Convergence of div(a grad u) = f with Dirichlet/Neumann data over a refinement list");
  add_common(cmd, *a);
  cmd->add_option("--n", a->n, "Refinement list: intervals per direction (layout A, dx = 1/n)")->capture_default_str();
  cmd->add_option("--seeds", a->seeds, "Comma-separated seeds: mean and spread over them (overrides --seed)");
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "Also plot error_inf against h (log-log) into this PNG file");
  add_columns_option(cmd, a->out,
                     {"method", "n", "N", "particles", "spacing", "error_inf", "order_inf", "error_l2", "order_l2", "mmatrix",
                      "infeasible", "solver_iterations", "seconds_total"});  // N: built-in clouds; particles, spacing: files
  auto file = std::make_shared<CloudFileArgs>();
  cmd->add_option("--cloud-file-pattern", file->pattern,
                  "Study on the user's clouds: a CSV file name with {n}, replaced by each --n (e.g. cloud_{n}.csv); "
                  "--u required, --f/--g/--q default from it");
  cmd->add_option("--h", file->h, "With --cloud-file-pattern: absolute support radius (default: --h-factor x the "
                                  "robust spacing of each file)");
  add_geometry_options(cmd, *file, true);
  add_column_options(cmd, *file, "--cloud-file-pattern");
  auto het = std::make_shared<HeterogeneousArgs>();
  add_heterogeneous_options(cmd, *het);
  auto config = std::make_shared<std::string>();
  add_config_option(cmd, *config);
  cmd->callback([a, file, het, cmd, config] {
    if (!config->empty()) {
      apply_problem_file(*cmd, *config);
      reject_output_over_input(*cmd);  // the file may have set either side
    }
    validate_output(a->out);
    if (is_heterogeneous_problem(a->problem)) return study_heterogeneous(*a, *het, *cmd);
    reject_group_options(*cmd, heterogeneous_group, "--problem spe-channel, spe-lognormal or spe10");
    const bool user_cloud = !file->pattern.empty() || !file->geometry.empty();
    if (!user_cloud) validate_columns(a->out, to_table(BvpStudyResult{}).columns);
    if (user_cloud) return study_cloud_files(*a, *file, *cmd);
    for (const char* opt : {"--spacing", "--fill", "--neumann-where", "--dirichlet-where"})
      check<ConfigError>(cmd->count(opt) == 0, opt, " needs --geometry");
    reject_column_options(*cmd, "--cloud-file-pattern");
    BvpStudyParams p = to_params(*a, parse_name_list(a->methods, "--method"));
    p.n = parse_int_list(a->n, "--n");
    if (!a->seeds.empty()) {
      p.seeds.clear();
      for (int s : parse_int_list(a->seeds, "--seeds")) p.seeds.push_back(static_cast<std::uint64_t>(s));
    }
    // The [SPE] problems are read by the paper's relative error (95) and monotonicity; a
    // tensor mobility adds the count of negative weights to the usual columns.
    if (p.problem == "spe-dirichlet" || p.problem == "spe-mixed")
      a->out.key_columns = {"method", "n", "dof", "error_rel", "error_rel_std", "order_rel", "mmatrix",
                            "negative_transmissibilities", "xi_max", "infeasible"};
    else if (!p.mobility.empty())
      a->out.key_columns.insert(a->out.key_columns.begin() + 10, "negative_transmissibilities");
    run_study_on_ranks_if_large(p);
    p.communicator = communicator();
    Progress progress;
    p.progress = [&progress](const std::string& label, double f) { progress.update(label, f); };
    const BvpStudyResult r = run_bvp_study(p);
    print_warnings(r.warnings, false);  // the rows of a study's runs are not kept: no list
    Json meta = metadata_json(r);
    meta["peak_memory_mib"] = max_over_ranks(p.communicator, peak_memory_mib());
    meta["ranks"] = p.communicator.size();
    emit(to_table(r), a->out, meta, "h", "error_inf", "method",
         p.problem + " " + a->cloud + " " + std::to_string(p.dim) + "D");
  });
}

void add_solve_command(CLI::App& app) {
  auto a = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand("solve", "Solve one boundary value problem and write the fields to a VTU file");
  add_common(cmd, *a);
  auto np = std::make_shared<int>(40);
  auto file = std::make_shared<CloudFileArgs>();
  cmd->add_option("--n", *np, "Intervals per direction (layout A, dx = 1/n)")->capture_default_str();
  cmd->add_option("--cloud-file", file->path,
                  "Solve on this cloud file (CSV x,y,z,tag[,nx,ny,nz][,extra columns], VTU/VTP with point arrays tag[, normals, ...], or a Gmsh .msh mesh whose nodes are the particles) instead of a built-in one: tags and "
                  "normals from the file, --f/--g/--q/--a evaluated at its points or taken from its columns "
                  "(--f-column ...), --u optional (errors only with it)");
  cmd->add_option("--h", file->h, "With --cloud-file: absolute support radius (default: --h-factor x the cloud's "
                                  "robust spacing, see README)");
  cmd->add_option("--csv", file->csv, "With --cloud-file: also write the fields as CSV (x,y,z,tag,u,...)");
  add_geometry_options(cmd, *file, false);
  add_column_options(cmd, *file, "--cloud-file");
  cmd->add_option("--vtu", a->vtu, "Write U, exact u, error and local residual to this VTU file (none without it; "
                                  "under mpirun a .pvtu with one piece per rank; one .vtu on the ranks --ranks auto starts)");
  cmd->add_option("--vtu-format", a->vtu_format, "VTU data: binary (base64, exact, smaller) or ascii")->capture_default_str();
  cmd->add_option("--format", a->out.format, "Summary format: md, csv or json")->capture_default_str();
  cmd->add_option("--plot", a->out.plot, "Also draw u (and, with an exact u, the error) into this PNG file "
                                         "(2D: filled contours; 1D: curves; 3D: the mid-plane z slice)");
  auto config = std::make_shared<std::string>();
  add_config_option(cmd, *config);
  cmd->callback([a, np, file, cmd, config] {
    if (!config->empty()) {
      apply_problem_file(*cmd, *config);
      reject_output_over_input(*cmd);  // the file may have set either side
    }
    (void)parse_vtu_format(a->vtu_format);  // checked before any work
    validate_output(a->out);
    if (!file->path.empty() || !file->geometry.empty()) return solve_cloud_file(*a, *file, *cmd);
    for (const char* opt : {"--spacing", "--fill", "--neumann-where", "--dirichlet-where"})
      check<ConfigError>(cmd->count(opt) == 0, opt, " needs --geometry");
    reject_column_options(*cmd, "--cloud-file");
    const auto methods = parse_name_list(a->methods, "--method");
    check<ConfigError>(methods.size() == 1, "vrsph solve takes exactly one --method");
    BvpStudyParams p = to_params(*a, methods);
    p.n = {*np};
    run_study_on_ranks_if_large(p);
    p.communicator = communicator();
    // Distributed: a piece per rank and a .pvtu that lists them (ParaView opens it as one),
    // except on ranks that --ranks auto started: the user asked one process for one .vtu
    // file and a plot, and gets them (the fields gathered, rank 0 writes).
    const bool whole = p.communicator.distributed() && ranks_started_automatically();
    std::string vtu = a->vtu;
    if (p.communicator.distributed() && !whole) {
      check<ConfigError>(a->out.plot.empty(), "--plot draws the whole field on one rank: not available under mpirun "
                         "(open the .pvtu in ParaView)");
      if (!vtu.empty()) vtu = pvtu_path(vtu);
    }
    std::vector<std::string> warnings;
    PointCloud cloud;
    const BvpRun r = run_bvp(p, methods.front(), *np, a->seed, true, &warnings, &cloud);
    print_warnings(warnings);
    print_infeasible_rows(r.method + " n=" + std::to_string(r.n), p.communicator.distributed() ? PointCloud{} : cloud,
                          r.infeasible_particles, r.infeasible_residuals);
    Eigen::MatrixXd U(r.U.size(), 1), ex(r.U.size(), 1), err(r.U.size(), 1), res(r.U.size(), 1);
    U.col(0) = r.U;
    ex.col(0) = r.exact;
    err.col(0) = r.U - r.exact;
    res.col(0) = r.local_residual;
    const std::vector<PointField> fields{{"U", U}, {"u_exact", ex}, {"error", err}, {"local_residual", res}};
    fault_point(p.communicator, "output");  // outside any collective: the MPI tests' abort path
    if (whole && (!vtu.empty() || !a->out.plot.empty())) {
      const WholeFields all = gather_whole(p.communicator, cloud, fields);
      collective(p.communicator, [&] {
        if (!p.communicator.is_root()) return;
        if (!vtu.empty()) write_vtu(vtu, all.cloud, all.fields, parse_vtu_format(a->vtu_format));
        if (!a->out.plot.empty()) {
          const Field u = all.fields[0].values.col(0), exact = all.fields[1].values.col(0);
          plot_solution(all.cloud, u, &exact, a->out.plot, r.method + " n=" + std::to_string(r.n));
        }
      });
    } else if (vtu.empty()) {
    } else if (p.communicator.distributed()) {
      collective(p.communicator, [&] {
        write_pvtu_piece(vtu, p.communicator.rank(), p.communicator.size(), cloud, fields, parse_vtu_format(a->vtu_format));
      });
    } else {
      write_vtu(vtu, cloud, fields, parse_vtu_format(a->vtu_format));
    }
    if (!whole && !a->out.plot.empty()) plot_solution(cloud, r.U, &r.exact, a->out.plot, r.method + " n=" + std::to_string(r.n));
    Table t;
    t.columns = {"method", "n", "N", "unknowns", "h", "error_inf", "error_l2", "mmatrix", "infeasible", "solver",
                 "solver_iterations", "solver_residual", "seconds_total", "vtu", "ranks"};
    t.add_row({{"method", r.method}, {"n", static_cast<long long>(r.n)}, {"N", static_cast<long long>(r.particles)},
               {"unknowns", static_cast<long long>(r.unknowns)}, {"h", r.h}, {"error_inf", r.errors.all.linf},
               {"error_l2", r.errors.all.l2}, {"mmatrix", r.m_matrix}, {"infeasible", static_cast<long long>(r.infeasible)},
               {"solver", r.solve.solver}, {"solver_iterations", static_cast<long long>(r.solve.iterations)},
               {"solver_residual", r.solve.residual},
               {"seconds_total", r.seconds_cloud + r.seconds_data + r.seconds_neighbours + r.seconds_stencil + r.seconds_assemble +
                                     r.seconds_solve},
               {"vtu", vtu},
               {"ranks", static_cast<long long>(p.communicator.size())}});
    std::cout << solve_summary(t, a->out.format, warnings, r.infeasible_particles);
  });
}

}  // namespace vrsph::cli
