// SPDX-License-Identifier: BSD-3-Clause
// `vrsph diffuse`: time-dependent diffusion ([SPE] §4.4 plate flow, Table 1) with explicit
// Euler, backward Euler or Crank–Nicolson, an error history (CSV), a VTU time series (.pvd)
// and Table 1 beside the published values.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <vrsph/io/json.hpp>
#include <vrsph/reproduce/spe_problems.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/cloud/box_faces.hpp>
#include <vrsph/problem/diffusion.hpp>
#include <vrsph/problem/diffusion_from_expressions.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#include "../vtu_series.hpp"

namespace vrsph::cli {

namespace {
struct DiffuseArgs {
  std::string problem = "spe-plate", methods = "m-sph", scheme = "explicit", nu, report_times, history, vtu_series,
              kernel = "cubic-spe", solver = "auto", petsc_options;
  // --problem custom: [0,1]^d, n intervals, expressions in x, y, z, t.
  std::string u, coef, mobility, s, g, q, u0, neumann, periodic, cloud = "uniform";
  int dim = 2, n = 20;
  double delta = 0.5;
  std::uint64_t seed = 1;
  std::vector<std::string> method_opts;
  double dx = 0.1, f = 1.001, dt = 0, t_end = 10, nu_limit = 0.25;
  bool allow_unstable = false;
  OutputOptions out;
};

}  // namespace

DiffusionProblem custom_problem(const DiffuseArgs& a) {
  check<ConfigError>(a.dim >= 1 && a.dim <= 3, "--dim must be 1, 2 or 3, got ", a.dim);
  check<ConfigError>(a.n >= 2 && a.n <= 100000, "--n must be in 2..100000, got ", a.n);
  CloudSpec spec;
  spec.family = parse_cloud_family(a.cloud);
  check<ConfigError>(spec.family == CloudFamily::Uniform || spec.family == CloudFamily::Perturbed,
                     "--cloud for diffuse is uniform or perturbed, got ", a.cloud);
  spec.box = Domain::unit_box(a.dim);
  spec.box.set_periodic(a.periodic);
  spec.n = a.n;
  spec.delta = a.delta;
  spec.seed = a.seed;
  check_study_settings(a.dim, 1, a.delta, 0);
  StudyCloud sc = make_study_cloud(spec);
  if (!a.neumann.empty()) retag_neumann_faces(sc.cloud, parse_box_faces(parse_name_list(a.neumann, "--neumann"), a.dim), sc.dx);
  DiffusionExpressions e;
  e.u = a.u;
  e.a = a.coef;
  if (!a.mobility.empty()) e.mobility = parse_expression_list(a.mobility, "--mobility");
  e.s = a.s;
  e.g = a.g;
  e.q = a.q;
  e.u0 = a.u0;
  return diffusion_from_expressions(std::move(sc.cloud), e);
}

namespace {
// The problem (the [SPE] plate or a custom one) and its checks.
DiffusionProblem diffusion_problem(DiffuseArgs& a, const CLI::App& cmd, const std::string& custom) {
  if (!a.u.empty() && cmd.count("--problem") == 0) a.problem = "custom";
  check<ConfigError>(a.problem == "spe-plate" || a.problem == "custom", "unknown diffusion problem '", a.problem,
                     "' (known: spe-plate, custom)");
  check<ConfigError>(!(cmd.count("--dt") && cmd.count("--nu")), "give --dt or --nu, not both");
  check<ConfigError>(std::isfinite(a.f) && a.f > 0, "--h-factor must be positive and finite, got ", a.f);
  const bool is_custom = a.problem == "custom";
  if (!is_custom) reject_group_options(cmd, custom, "--problem custom");
  check<ConfigError>(!is_custom || cmd.count("--dx") == 0, "--dx does not apply to --problem custom (dx = 1/--n)");
  return is_custom ? custom_problem(a) : spe_plate_problem(a.dx);
}

// diffuse()'s options from the command line (dt is set per run).
DiffusionOptions diffusion_options(const DiffuseArgs& a, const CLI::App& cmd, Real dx) {
  DiffusionOptions o;
  o.communicator = communicator();
  o.method = a.methods;
  const auto per_method = parse_method_options(a.method_opts, {a.methods});
  note_row_forms({a.methods}, per_method, StencilUse::Values);
  o.method_options = options_for(per_method, a.methods);
  o.kernel = parse_kernel(a.kernel);
  o.h_factor = 2 * a.f;
  o.spacing = dx;
  o.scheme = parse_time_scheme(a.scheme);
  o.solver.type = parse_solver(a.solver);
  o.solver.petsc_options = a.petsc_options;
  for (const char* opt : {"--solver", "--petsc-options"})
    check<ConfigError>(o.scheme != TimeScheme::Explicit || cmd.count(opt) == 0, opt,
                       " applies to --scheme implicit or cn (the explicit scheme solves nothing)");
  o.t_end = a.t_end;
  o.nu_limit = a.nu_limit;
  o.allow_unstable = a.allow_unstable;
  check<ConfigError>(std::isfinite(a.t_end) && a.t_end > 0 && a.t_end <= 1e6, "--t-end must be in (0, 1e6], got ",
                     a.t_end);
  if (a.report_times.empty()) {  // 1, 2, ... up to t_end, and t_end itself
    for (int k = 1; k <= static_cast<int>(std::floor(a.t_end + 1e-9)); ++k) o.report_times.push_back(k);
    if (o.report_times.empty() || std::abs(o.report_times.back() - a.t_end) > 1e-9) o.report_times.push_back(a.t_end);
  } else {
    o.report_times = parse_real_list(a.report_times, "--report-times");
  }
  return o;
}

// The runs' stability numbers ν = Δt max(a) / ℓ²: --nu, or the one --dt gives.
std::vector<double> stability_numbers(const DiffuseArgs& a, const CLI::App& cmd, Real ell, Real a_max) {
  std::vector<double> nus = a.nu.empty() ? std::vector<double>{0.2} : parse_real_list(a.nu, "--nu");
  if (cmd.count("--dt")) {
    check<ConfigError>(std::isfinite(a.dt) && a.dt > 0, "--dt must be positive and finite, got ", a.dt);
    nus = {a.dt * a_max / (ell * ell)};
  }
  for (double nu : nus) check<ConfigError>(nu > 0, "--nu must be positive, got ", nu);
  return nus;
}

// One run's rows at the report times, beside [SPE] Table 1 where the run is the paper's.
void add_rows(Table& t, const DiffusionOptions& o, const DiffusionResult& r, double nu, bool paper_columns) {
  const auto& table1 = spe_plate_table1();
  const std::array<double, 4> table_nu{0.1, 0.2, 0.25, 0.26};
  int column = -1;
  for (int c = 0; c < 4; ++c)
    if (std::abs(nu - table_nu[static_cast<std::size_t>(c)]) < 1e-12) column = c;
  for (std::size_t k = 0; k < o.report_times.size(); ++k) {
    const Real T = o.report_times[k], e = r.report_error[k];
    const int row = static_cast<int>(std::lround(T)) - 1;
    const bool published = paper_columns && column >= 0 && std::abs(T - std::round(T)) < 1e-12 && row >= 0 && row < 10;
    t.add_row({{"scheme", to_string(o.scheme)}, {"nu", nu}, {"dt", o.dt}, {"t", T}, {"error_inf", e},
               {"log10_error", e > 0 ? std::log10(e) : std::nan("")},
               {"paper_log10_error", published ? table1[static_cast<std::size_t>(row)][static_cast<std::size_t>(column)]
                                               : std::nan("")},
               {"steps", static_cast<long long>(r.steps)}, {"particles", static_cast<long long>(r.particles)},
               {"seconds", r.seconds}, {"seconds_setup", r.seconds_setup},
               {"seconds_factorisation", r.seconds_factorisation}, {"seconds_per_step", r.seconds_per_step},
               {"solver", r.solver}, {"solver_iterations", r.solver_iterations},
               {"dt_limit", r.dt_limit > 0 ? r.dt_limit : std::nan("")}});
  }
}

// u and its error at the first step at or after each report time (and t = 0), as a VTU series.
std::function<void(Real, const Field&)> series_writer(VtuSeries& series, const DiffusionProblem& problem,
                                                      const std::vector<Real>& report_times) {
  auto next_report = std::make_shared<std::size_t>(0);
  return [&series, &problem, &report_times, next_report](Real time, const Field& u) {
    if (!(time == 0 || (*next_report < report_times.size() && time >= report_times[*next_report] - 1e-12))) return;
    std::vector<PointField> fields{{"u", Eigen::MatrixXd(u)}};
    if (problem.exact) {
      Eigen::MatrixXd error(u.size(), 1);
      for (Index i = 0; i < u.size(); ++i)
        error(i, 0) = u[i] - problem.exact(problem.cloud.positions[static_cast<std::size_t>(i)], time);
      fields.push_back({"error", std::move(error)});
    }
    series.write(time, problem.cloud, fields);
    if (time > 0) ++*next_report;
  };
}

void run_diffuse(DiffuseArgs& a, const CLI::App& cmd, const std::string& custom) {
  validate_output(a.out);
  const DiffusionProblem problem = diffusion_problem(a, cmd, custom);
  const bool is_custom = a.problem == "custom";
  const Communicator& comm = communicator();
  check<ConfigError>(!comm.distributed() || a.vtu_series.empty(), "--vtu-series writes the whole field on one "
                     "rank: not available under mpirun");
  const Index total = problem.cloud.size();
  // Under mpirun each rank passes its consecutive slice of the particles (diffuse repartitions them).
  const DiffusionProblem mine = comm.distributed() ? part_of(problem, total * comm.rank() / comm.size(),
                                                             total * (comm.rank() + 1) / comm.size())
                                                   : DiffusionProblem();
  const Real dx = is_custom ? 1.0 / a.n : a.dx;
  const Real a_max = problem.mobility.size() ? problem.mobility.maxCoeff() : problem.a.size() ? problem.a.maxCoeff() : 1.0;
  DiffusionOptions o = diffusion_options(a, cmd, dx);
  const Real ell = a.f * dx;  // smoothing length; ν = Δt max(a) / ℓ² (plate: a = 1/Re = 1)
  const std::vector<double> nus = stability_numbers(a, cmd, ell, a_max);
  const bool paper_columns = !is_custom && o.scheme == TimeScheme::Explicit && std::abs(a.dx - 0.1) < 1e-12;
  Table t;
  t.columns = {"scheme", "nu", "dt", "t", "error_inf", "log10_error", "paper_log10_error", "steps", "particles",
               "seconds", "seconds_setup", "seconds_factorisation", "seconds_per_step", "solver", "solver_iterations", "dt_limit"};
  std::string history;
  Progress progress;
  for (std::size_t run = 0; run < nus.size(); ++run) {
    o.dt = nus[run] * ell * ell / a_max;
    std::unique_ptr<VtuSeries> series;
    if (!a.vtu_series.empty() && run == 0) series = std::make_unique<VtuSeries>(a.vtu_series);
    o.on_step = series ? series_writer(*series, problem, o.report_times) : nullptr;
    o.progress = [&](double f) { progress.update(detail::concat("nu = ", nus[run]), (static_cast<double>(run) + f) / static_cast<double>(nus.size())); };
    const DiffusionResult r = diffuse(comm.distributed() ? mine : problem, o);
    // A run that diverged is a result only for a stability study that asked for it.
    if (r.diverged && !a.allow_unstable) throw NumericalError(r.warnings.back());
    for (const auto& w : r.warnings) std::cerr << "vrsph: warning: " << w << '\n';
    for (std::size_t k = 0; k < r.times.size(); ++k) history += detail::concat(nus[run], ",", r.times[k], ",", r.error_inf[k], "\n");
    add_rows(t, o, r, nus[run], paper_columns);
  }
  if (!a.history.empty())
    write_file(a.history, "error history", [&](std::ostream& f) { f << "nu,t,error_inf\n" << history; });
  Json meta;
  meta["problem"] = a.problem;
  meta["particles"] = problem.cloud.size();
  meta["neumann_particles"] = problem.cloud.count(Tag::Neumann);
  if (is_custom) meta["u"] = a.u;
  emit(t, a.out, meta, "t", "log10_error", "nu", (is_custom ? "custom, " : "plate flow, ") + a.scheme, false);
}
}  // namespace

void add_diffuse_command(CLI::App& app) {
  auto a = std::make_shared<DiffuseArgs>();
  auto* cmd = app.add_subcommand("diffuse", "Time-dependent diffusion du/dt = div(a grad u) + s: [SPE] plate flow "
                                            "(Table 1) with explicit, implicit or Crank-Nicolson steps");
  cmd->add_option("--problem", a->problem, "spe-plate ([SPE] §4.4: start-up channel flow on [0,2]x[-1,1], Re = 1) or "
                                           "custom ([0,1]^d, --u/--a/--s/--g/--q expressions in x, y, z, t); --u implies custom")
      ->capture_default_str();
  const std::string custom = "Custom problem (--problem custom)";
  cmd->add_option("--u", a->u, "Exact solution u(x,y,z,t): s, g, q and u0 default from it")->group(custom);
  cmd->add_option("--a", a->coef, "Coefficient a(x,y,z) > 0 (default 1)")->group(custom);
  cmd->add_option("--mobility", a->mobility, "Diagonal mobility m1,m2[,m3] instead of --a")->group(custom);
  cmd->add_option("--s", a->s, "Source s(x,y,z,t) (default du/dt - div(a grad u))")->group(custom);
  cmd->add_option("--g", a->g, "Dirichlet data g(x,y,z,t) (default u)")->group(custom);
  cmd->add_option("--q", a->q, "Neumann data q = n.a grad u (x,y,z,t) (default from u)")->group(custom);
  cmd->add_option("--u0", a->u0, "Initial values u0(x,y,z) (default u at t = 0)")->group(custom);
  cmd->add_option("--neumann", a->neumann, "Neumann faces x0,x1,y0,y1,z0,z1 or all (default none)")->group(custom);
  cmd->add_option("--periodic", a->periodic, "Periodic axes x,y,z or all of [0,1]^d (no boundary particles there)")
      ->group(custom);
  cmd->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->group(custom)->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction of [0,1]^d (layout A, dx = 1/n)")->group(custom)->capture_default_str();
  cmd->add_option("--cloud", a->cloud, "uniform or perturbed")->group(custom)->capture_default_str();
  cmd->add_option("--delta", a->delta, "Perturbation amplitude in units of dx")->group(custom)->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->group(custom)->check(seed_validator())
      ->capture_default_str();
  cmd->add_option("--method", a->methods, "Method (div-a-grad stencil)")->capture_default_str();
  cmd->add_option("--method-opt", a->method_opts, "Method option key=value (repeatable)");
  cmd->add_option("--solver", a->solver,
                  "Implicit schemes: solver of I - theta dt L, set up once and reused at every step: auto (direct when "
                  "small, else petsc), petsc (GMRES + BoomerAMG), umfpack, sparselu, bicgstab")
      ->capture_default_str();
  cmd->add_option("--petsc-options", a->petsc_options, "PETSc options for --solver petsc/auto");
  cmd->add_option("--scheme", a->scheme, "explicit (Euler), implicit (backward Euler) or cn (Crank-Nicolson)")
      ->capture_default_str();
  cmd->add_option("--nu", a->nu, "Comma-separated stability numbers nu = dt/(Re l^2), one run each ([SPE] Table 1: "
                                 "0.1,0.2,0.25,0.26); default 0.2");
  cmd->add_option("--dt", a->dt, "Time step instead of --nu");
  cmd->add_option("--t-end", a->t_end, "End time (the run stops at the first step at or after it)")->capture_default_str();
  cmd->add_option("--dx", a->dx, "Particle spacing (0.1 reproduces [SPE] Table 1, docs/spe_tables.md)")->capture_default_str();
  cmd->add_option("--h-factor", a->f, "[SPE]'s f = l/dx: support radius 2 f dx (1.001 reproduces [SPE] Table 1)")->capture_default_str();
  cmd->add_option("--kernel", a->kernel, "Kernel")->capture_default_str();
  cmd->add_option("--nu-limit", a->nu_limit, "Largest nu the explicit scheme accepts")->capture_default_str();
  cmd->add_flag("--allow-unstable", a->allow_unstable, "Run the explicit scheme above --nu-limit anyway (stability study)");
  cmd->add_option("--report-times", a->report_times, "Times of the error table (default 1, 2, ..., t_end)");
  cmd->add_option("--history", a->history, "Write the error after every step to this CSV file (nu, t, error_inf)");
  cmd->add_option("--vtu-series", a->vtu_series, "Write u and its error at the report times as PREFIX_NNNN.vtu and a "
                                                 "PREFIX.pvd collection for ParaView (first --nu only)");
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "Also plot log10 of the error against time per nu (PNG)");
  cmd->callback([a, cmd, custom] { run_diffuse(*a, *cmd, custom); });
}

}  // namespace vrsph::cli
