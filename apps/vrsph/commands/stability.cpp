// SPDX-License-Identifier: BSD-3-Clause
// `vrsph stability`: von Neumann growth factors of a method's Laplacian ([SPE] Fig. 5) and the
// statistics of the monotonicity diagnostic ξ ([SPE] Fig. 6).
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/stability.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"

namespace vrsph::cli {

namespace {
struct StabilityArgs {
  std::string methods = "m-sph", cloud = "uniform", layout = "vertex", kernel = "cubic-spe", neighbours;
  std::vector<std::string> method_opts;
  int dim = 2, n = 20, k = 16, configurations = 50;
  double h_factor = 2.4, delta = 0.1001, tau = 0.25;
  std::uint64_t seed = 1;
  bool xi_statistics = false;
  OutputOptions out;
};

// The λ clouds for share/plot_stability.py: at most `cap` points per method (evenly strided).
void plot_growth_factors(const StabilityResult& r, const std::string& png, const std::string& title) {
  Json j;
  j["title"] = title;
  for (const auto& row : r.rows) {
    Json pts = Json::array();
    const std::size_t cap = 40000, stride = std::max<std::size_t>(1, row.samples.size() / cap);
    for (std::size_t s = 0; s < row.samples.size(); s += stride)
      pts.push_back(Json::array({row.samples[s].real(), row.samples[s].imag(), row.sample_is_boundary[s] ? 1 : 0}));
    j["methods"][row.method] = pts;
  }
  const TemporaryFile data("vrsph-stability", ".json");
  write_file(data.path(), "temporary plot data", [&](std::ostream& f) { f << j.dump(); });
  run_plot_script("plot_stability.py", data.path(), png);
}
}  // namespace

void add_stability_command(CLI::App& app) {
  auto a = std::make_shared<StabilityArgs>();
  auto* cmd = app.add_subcommand("stability", "Von Neumann growth factors of a method's Laplacian ([SPE] Fig. 5), or "
                                              "the statistics of the monotonicity diagnostic xi (Fig. 6)");
  cmd->add_option("--method", a->methods, "Comma-separated method names")->capture_default_str();
  cmd->add_option("--method-opt", a->method_opts, "Method option key=value, or method:key=value (repeatable)");
  cmd->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->capture_default_str();
  cmd->add_option("--cloud", a->cloud, "uniform or perturbed (U(-delta dx, delta dx))")->capture_default_str();
  cmd->add_option("--layout", a->layout, "vertex (layout A) or cells (layout B)")->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction of the unit box")->capture_default_str();
  cmd->add_option("--delta", a->delta, "Perturbation amplitude in units of dx")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed")->check(seed_validator())->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius / dx (2.4 = [SPE] f = 1.2)")->capture_default_str();
  cmd->add_option("--kernel", a->kernel, "Kernel")->capture_default_str();
  cmd->add_option("--tau", a->tau, "Dimensionless step tau: lambda = 1 + tau l^2 e^{-ik.x_j} L[e^{ik.x}]_j")->capture_default_str();
  cmd->add_option("--k", a->k, "Wave vectors per direction on [-pi/dx, pi/dx]")->capture_default_str();
  cmd->add_flag("--xi-statistics", a->xi_statistics,
                "Instead: mean and spread of |xi| over random neighbour sets in the unit disc (h = 1, Fig. 6)");
  cmd->add_option("--neighbours", a->neighbours, "With --xi-statistics: neighbour counts (default 4,8,16,32,64,125,250,500)");
  cmd->add_option("--configurations", a->configurations, "With --xi-statistics: random sets per count")->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "Also plot: the complex-plane cloud of lambda with the unit circle (Fig. 5), "
                                         "or mean |xi| against the neighbour count (Fig. 6)");
  cmd->callback([a, cmd] {
    validate_output(a->out);
    if (a->xi_statistics) {
      for (const char* opt : {"--method", "--method-opt", "--cloud", "--layout", "--n", "--delta", "--h-factor",
                              "--kernel", "--tau", "--k"})
        check<ConfigError>(cmd->count(opt) == 0, opt, " does not apply with --xi-statistics");
      const std::vector<int> counts = a->neighbours.empty() ? std::vector<int>{4, 8, 16, 32, 64, 125, 250, 500}
                                                            : parse_int_list(a->neighbours, "--neighbours");
      const auto rows = xi_statistics(a->dim, counts, a->configurations, a->seed);
      emit(to_table(rows), a->out, Json::object({{"figure", "[SPE] Fig. 6"}}), "neighbours", "xi_mean", "sets", "|xi| ([SPE] Fig. 6)");
      return;
    }
    for (const char* opt : {"--neighbours", "--configurations"})
      check<ConfigError>(cmd->count(opt) == 0, opt, " applies with --xi-statistics only");
    StabilityParams p;
    p.methods = parse_name_list(a->methods, "--method");
    p.method_options = parse_method_options(a->method_opts, p.methods);
    note_row_forms(p.methods, p.method_options, StencilUse::Values);
    p.dim = a->dim;
    p.cloud = parse_cloud_family(a->cloud);
    check<ConfigError>(a->layout == "vertex" || a->layout == "cells", "--layout must be vertex or cells, got '",
                       a->layout, "'");
    p.layout = a->layout == "cells" ? Layout::CellCentred : Layout::Vertex;
    p.n = a->n;
    p.delta = a->delta;
    p.seed = a->seed;
    p.support_factor = a->h_factor;
    p.kernel = parse_kernel(a->kernel);
    p.tau = a->tau;
    p.k_samples = a->k;
    p.keep_samples = !a->out.plot.empty();
    const StabilityResult r = run_stability(p);
    OutputOptions table_only = a->out;
    table_only.plot.clear();
    emit(to_table(r), table_only, Json::object({{"figure", "[SPE] Fig. 5"}}), "", "", "", "");
    if (!a->out.plot.empty())
      plot_growth_factors(r, a->out.plot, detail::concat("growth factors, ", a->cloud, ", tau = ", a->tau));
  });
}

}  // namespace vrsph::cli
