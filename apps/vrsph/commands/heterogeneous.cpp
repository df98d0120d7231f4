// SPDX-License-Identifier: BSD-3-Clause
// `vrsph study --problem spe-channel|spe-lognormal|spe10`: flow through a heterogeneous
// permeability field, every method against the TPFA reference, and the Krylov study of
// [SPE] Figs. 11-12 (--krylov).
#include <iostream>
#include <vrsph/io/json.hpp>
#include <vrsph/reproduce/heterogeneous_study.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/io/vtu.hpp>
#include "heterogeneous_args.hpp"

namespace vrsph::cli {

void add_heterogeneous_options(CLI::App* cmd, HeterogeneousArgs& h) {
  auto opt = [&](const std::string& name, auto& value, const std::string& help) {
    return cmd->add_option(name, value, help)->group(heterogeneous_group);
  };
  opt("--perm-file", h.perm_file,
      "spe10: permeability file in the spe_perm.dat layout (whitespace-separated k_x block, k_y block[, k_z block], I "
      "fastest, then J, then K; one block = isotropic)");
  opt("--perm-grid", h.perm_grid, "spe10: the file's grid I,J,K")->capture_default_str();
  opt("--perm-subset", h.perm_subset,
      "spe10: the cells used, 1-based inclusive ranges I0:I1,J0:J1,K0:K1 (square in the field's dimension; default "
      "2D 1:60,1:60,85:85 = layer 85 as in [SPE], 3D 1:60,1:60,1:60)");
  opt("--contrast", h.contrast, "spe-channel: k_channel / k_background")->capture_default_str();
  opt("--channels", h.channels, "spe-channel: number of channels (0: 4 in 2D, 8 in 3D)")->capture_default_str();
  opt("--sigma-ln", h.sigma_ln, "spe-lognormal: standard deviation of ln k")->capture_default_str();
  opt("--correlation-length", h.correlation_length,
      "spe-lognormal: correlation length of ln k in units of the domain (covariance exp(-r^2/l^2))")
      ->capture_default_str();
  opt("--kz-ratio", h.kz_ratio, "spe-channel, spe-lognormal in 3D: k_z / k_x")->capture_default_str();
  opt("--krylov", h.krylov,
      "Also run the Krylov study ([SPE] Figs. 11-12): GMRES on every method's system with these preconditioners, "
      "comma-separated: none, jacobi, ilu (ILU(0)), amg (BoomerAMG)");
  opt("--krylov-restart", h.restart, "GMRES restart length of the Krylov study")->capture_default_str();
  opt("--krylov-rtol", h.rtol, "Relative tolerance (true residual) of the Krylov study")->capture_default_str();
  opt("--krylov-max-it", h.max_iterations, "Iteration cap of the Krylov study")->capture_default_str();
  opt("--krylov-output", h.krylov_output, "Krylov study: write its table (format of --format) to this file");
  opt("--history", h.history, "Krylov study: write the residual histories as CSV (method, preconditioner, iteration, "
                              "residual) to this file");
  opt("--vtu", h.vtu, "Write the cloud with K, the TPFA pressure and every method's u to this VTU file");
}

namespace {

std::array<std::array<int, 2>, 3> parse_subset(const std::string& text) {
  std::array<std::array<int, 2>, 3> out{};
  const auto parts = parse_name_list(text, "--perm-subset");
  check<ConfigError>(parts.size() == 3, "--perm-subset needs three ranges I0:I1,J0:J1,K0:K1, got '", text, "'");
  for (std::size_t a = 0; a < 3; ++a) {
    const auto colon = parts[a].find(':');
    const std::string lo = parts[a].substr(0, colon), hi = colon == std::string::npos ? lo : parts[a].substr(colon + 1);
    const auto l = parse_int_list(lo, "--perm-subset"), h = parse_int_list(hi, "--perm-subset");
    check<ConfigError>(l.size() == 1 && h.size() == 1, "--perm-subset: '", parts[a], "' is not a range like 1:60");
    out[a] = {l[0], h[0]};
  }
  return out;
}

void plot_krylov(const HeterogeneousStudyResult& r, const std::string& png) {
  const TemporaryFile data("vrsph-krylov", ".json");
  write_file(data.path(), "temporary plot data",
             [&](std::ostream& f) { f << to_json(krylov_history_table(r), metadata_json(r)); });
  run_plot_script("plot_krylov.py", data.path(), png);
}

void write_fields(const HeterogeneousStudyResult& r, const std::string& path) {
  const PointCloud& cloud = r.cloud;
  const Index N = cloud.size();
  const auto& field = r.params.field;
  std::vector<PointField> arrays;
  Eigen::MatrixXd K(N, field.dim), ref(N, 1);
  for (Index i = 0; i < N; ++i) {
    const Index c = field.cell_of(cloud.positions[static_cast<std::size_t>(i)]);
    K.row(i) = field.k.row(c);
    ref(i, 0) = r.reference[c];
  }
  arrays.push_back({"K", K});
  arrays.push_back({"u_tpfa", ref});
  for (const auto& run : r.runs)
    if (run.u.size() == N) arrays.push_back({"u_" + run.method, Eigen::MatrixXd(run.u)});
  write_vtu(path, cloud, arrays, VtuFormat::Binary);
}

// Options of the other studies that do not apply, and the field options of the other problems.
void reject_foreign_options(const StudyArgs& a, const HeterogeneousArgs& h, const CLI::App& cmd) {
  for (const char* o : {"--cloud", "--delta", "--perturb-boundary", "--regular-layer", "--h-mode", "--h-knn", "--neumann",
                        "--q", "--robin", "--beta", "--fix-constant", "--u", "--a", "--mobility", "--layout", "--f", "--g", "--seeds", "--periodic",
                        "--on-infeasible", "--cloud-file-pattern", "--h", "--geometry"})
    check<ConfigError>(cmd.count(o) == 0, o, " does not apply to ", a.problem,
                       " (the particles are the cell centres of the permeability grid, layout B, with u = 1 at y = 0, "
                       "u = 0 at y = 1 and no flow elsewhere)");
  const bool is_file = a.problem == "spe10";
  for (const char* o : {"--perm-file", "--perm-grid", "--perm-subset"})
    check<ConfigError>(is_file || cmd.count(o) == 0, o, " applies to --problem spe10 only");
  for (const char* o : {"--contrast", "--channels"})
    check<ConfigError>(a.problem == "spe-channel" || cmd.count(o) == 0, o, " applies to --problem spe-channel only");
  for (const char* o : {"--sigma-ln", "--correlation-length"})
    check<ConfigError>(a.problem == "spe-lognormal" || cmd.count(o) == 0, o, " applies to --problem spe-lognormal only");
  check<ConfigError>(!is_file || cmd.count("--kz-ratio") == 0, "--kz-ratio does not apply to spe10 (k_z is in the file)");
  for (const char* o : {"--krylov-restart", "--krylov-rtol", "--krylov-max-it", "--history", "--krylov-output"})
    check<ConfigError>(!h.krylov.empty() || cmd.count(o) == 0, o, " needs --krylov");
  check<ConfigError>(!h.krylov.empty() || a.out.plot.empty(), "--plot for ", a.problem,
                     " draws the Krylov residual histories: it needs --krylov");
}

// spe10: the file's field on the chosen cells.
PermeabilityField spe10_field(const HeterogeneousArgs& h, int dim) {
  check<ConfigError>(!h.perm_file.empty(), "--problem spe10 needs --perm-file (SPE10's spe_perm.dat is not shipped: "
                                           "R18; spe-channel and spe-lognormal are the built-in substitutes)");
  PermeabilityFileLayout layout;
  layout.dim = dim;
  const auto grid = parse_int_list(h.perm_grid, "--perm-grid");
  check<ConfigError>(grid.size() == 3, "--perm-grid needs three sizes I,J,K, got '", h.perm_grid, "'");
  layout.grid = {grid[0], grid[1], grid[2]};
  if (!h.perm_subset.empty()) layout.subset = parse_subset(h.perm_subset);
  else if (dim == 3) layout.subset = {{{1, 60}, {1, 60}, {1, 60}}};
  return read_permeability(h.perm_file, layout);
}

HeterogeneousStudyParams heterogeneous_params(const StudyArgs& a, const HeterogeneousArgs& h, const CLI::App& cmd) {
  const ProblemDefaults def = problem_defaults(a.problem);
  HeterogeneousStudyParams p;
  p.problem = a.problem;
  p.dim = a.dim_opt->count() ? a.dim : def.dim;
  check<ConfigError>(p.dim == 2 || p.dim == 3, a.problem, " is a 2D or 3D problem, got --dim ", p.dim);
  if (cmd.count("--method")) p.methods = parse_name_list(a.methods, "--method");
  std::vector<std::string> registered;
  for (const auto& m : p.methods)
    if (m != "tpfa") registered.push_back(m);
  p.method_options = parse_method_options(a.method_opts, registered);
  if (cmd.count("--n")) {
    const auto n = parse_int_list(a.n, "--n");
    check<ConfigError>(n.size() == 1, "--n for ", a.problem, " is one number of cells per axis (the field is "
                                      "generated on that grid), got ", n.size());
    check<ConfigError>(a.problem != "spe10", "--n does not apply to spe10: the grid is --perm-subset");
    p.n = n.front();
  }
  p.kernel = a.kernel_opt->count() ? parse_kernel(a.kernel) : def.kernel;
  p.support_factor = (a.h_factor_opt->count() ? a.h_factor : def.h_factor) * def.support_per_h_factor;
  p.solver = solver_options(a);
  p.infeasible_tolerance = a.infeasible_tol;
  p.channel.contrast = h.contrast;
  p.channel.channels = h.channels;
  p.channel.kz_ratio = p.lognormal.kz_ratio = h.kz_ratio;
  p.channel.seed = p.lognormal.seed = a.seed;
  p.lognormal.sigma_ln = h.sigma_ln;
  p.lognormal.correlation_length = h.correlation_length;
  if (a.problem == "spe10") p.field = spe10_field(h, p.dim);
  if (!h.krylov.empty()) p.krylov.preconditioners = parse_name_list(h.krylov, "--krylov");
  p.krylov.restart = h.restart;
  p.krylov.rtol = h.rtol;
  p.krylov.max_iterations = h.max_iterations;
  p.keep_fields = !h.vtu.empty();
  p.communicator = communicator();
  return p;
}

// The methods' table; the Krylov table (into the JSON, a file of its own, or after the
// methods' table), the residual histories, their plot and the fields.
void report_heterogeneous(const HeterogeneousStudyResult& r, const StudyArgs& a, const HeterogeneousArgs& h) {
  Json meta = metadata_json(r);
  meta["peak_memory_mib"] = peak_memory_mib();
  OutputOptions out = a.out;
  out.plot.clear();
  out.key_columns = {"method", "coefficient", "error_rel_vs_tpfa", "error_rms_rel_vs_tpfa", "outlet_flux",
                     "flux_error_vs_tpfa", "mmatrix", "min_u", "max_u", "monotone", "solver_iterations"};
  const bool root = communicator().is_root();  // rank 0 writes for all
  const TableFormat format = parse_table_format(a.out.format);
  const Table krylov = r.krylov.empty() ? Table{} : krylov_table(r);
  if (!r.krylov.empty()) {
    if (!h.krylov_output.empty()) {
      if (root)
        write_file(h.krylov_output, "Krylov study table", [&](std::ostream& f) { f << format_table(krylov, format); });
    } else if (format == TableFormat::Json) {
      meta["krylov_rows"] = json_rows(krylov);
    }
  }
  emit(to_table(r), out, meta, "", "", "", "");
  if (!root) return;
  if (!r.krylov.empty() && h.krylov_output.empty() && format != TableFormat::Json) {
    std::cout << "\nKrylov study: GMRES(" << r.params.krylov.restart << "), right preconditioning, rtol "
              << r.params.krylov.rtol << " on the true residual, zero initial guess\n\n"
              << format_table(krylov, format);
    check_stream(std::cout, "the Krylov table to standard output");
  }
  if (!h.history.empty())
    write_file(h.history, "Krylov residual histories", [&](std::ostream& f) { f << to_csv(krylov_history_table(r)); });
  if (!a.out.plot.empty()) plot_krylov(r, a.out.plot);
  if (!h.vtu.empty()) write_fields(r, h.vtu);
}
}  // namespace

void study_heterogeneous(const StudyArgs& a, const HeterogeneousArgs& h, const CLI::App& cmd) {
  reject_foreign_options(a, h, cmd);
  HeterogeneousStudyParams p = heterogeneous_params(a, h, cmd);
  Progress progress;
  p.progress = [&progress](const std::string& label, double f) { progress.update(label, f); };
  const HeterogeneousStudyResult r = run_heterogeneous_study(p);
  print_warnings(r.warnings, false);
  report_heterogeneous(r, a, h);
}

}  // namespace vrsph::cli
