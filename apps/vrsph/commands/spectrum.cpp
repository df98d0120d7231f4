// SPDX-License-Identifier: BSD-3-Clause
// `vrsph spectrum`: [AAR]'s vibration test, normalised spectra of methods beside lumped FEM.
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/reproduce/spectrum.hpp>
#include <vrsph/core/error.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"

namespace vrsph::cli {

namespace {
struct SpectrumArgs {
  std::string methods = "fpm2o", kernel = "gaussian", cloud = "uniform";
  int n = 101;
  double h_factor = 6, delta = 0.25;
  std::uint64_t seed = 1;
  std::vector<std::string> method_opts;
  OutputOptions out;
};

nlohmann::ordered_json finite_or_null(const std::vector<Real>& v) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (Real x : v) a.push_back(std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json());
  return a;
}
}  // namespace

void add_spectrum_command(CLI::App& app) {
  auto a = std::make_shared<SpectrumArgs>();
  auto* cmd = app.add_subcommand("spectrum", "[AAR] vibration test: normalised spectrum sqrt(lambda_n)/(n pi) of -K "
                                             "(fixed ends) beside lumped-mass linear FEM");
  cmd->add_option("--method", a->methods, "Comma-separated method names with a second-derivative stencil")->capture_default_str();
  cmd->add_option("--method-opt", a->method_opts, "Method option key=value, or method:key=value (repeatable)");
  cmd->add_option("--n", a->n, "Intervals: n + 1 equispaced particles, n - 1 unknowns ([AAR]: 101 -> 100)")->capture_default_str();
  cmd->add_option("--kernel", a->kernel, "Kernel (default: Gaussian with l = dx, as in [AAR])")->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius / dx (Gaussian: 6 = truncation at 6 l)")->capture_default_str();
  cmd->add_option("--cloud", a->cloud, "uniform or perturbed (interior particles U(-delta dx, delta dx))")->capture_default_str();
  cmd->add_option("--delta", a->delta, "Perturbation amplitude in units of dx")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed (perturbed)")->check(seed_validator())->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json (json: omega_ratio[] of the first method, "
                                             "spectra{} of all, fem_ratio[])")
      ->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "Plot omega_h/omega against n/N (PNG)");
  cmd->callback([a] {
    validate_output(a->out);
    const auto methods = parse_name_list(a->methods, "--method");
    const auto options = parse_method_options(a->method_opts, methods);
    note_row_forms(methods, options, StencilUse::Values);
    const CloudFamily family = parse_cloud_family(a->cloud);
    check<ConfigError>(family == CloudFamily::Uniform || family == CloudFamily::Perturbed,
                       "vrsph spectrum: --cloud must be uniform or perturbed");
    Table t;
    t.columns = {"method", "mode", "n_over_N", "omega_ratio"};
    nlohmann::ordered_json meta, spectra = nlohmann::ordered_json::object(), imag = nlohmann::ordered_json::object();
    const auto add_rows = [&t](const std::string& name, const std::vector<Real>& ratio) {
      for (std::size_t k = 0; k < ratio.size(); ++k)
        t.add_row({{"method", name},
                   {"mode", static_cast<long long>(k + 1)},
                   {"n_over_N", static_cast<Real>(k + 1) / static_cast<Real>(ratio.size())},
                   {"omega_ratio", ratio[k]}});
    };
    std::vector<std::string> warnings;
    // Dense O(n^3) eigenproblems: refuse what does not fit, say how long the rest takes. A
    // long run is timed first on a quarter of the intervals (a 64th of one problem's work),
    // and each finished problem re-times the ones left: the progress bar and the estimate
    // follow this machine's speed now, not a fixed rate.
    check_spectrum_size(a->n);
    const auto params_of = [&](const std::string& m) {
      SpectrumParams p;
      p.method = m;
      p.options = options_for(options, m);
      p.n = a->n;
      p.kernel = parse_kernel(a->kernel);
      p.h_factor = a->h_factor;
      p.cloud = family;
      p.delta = a->delta;
      p.seed = a->seed;
      return p;
    };
    double each = dense_spectrum_seconds(a->n);
    if (each * static_cast<double>(methods.size() + 1) > 2) each = calibrated_spectrum_seconds(params_of(methods.front()));
    const double total = each * static_cast<double>(methods.size() + 1);
    if (total > 10)
      std::cerr << "vrsph: spectrum: " << methods.size() + 1 << " dense eigenvalue problems of " << a->n - 1
                << " unknowns, about " << static_cast<long long>(std::ceil(total)) << " s in all (O(n^3), timed on "
                << std::max(3, a->n / 4) << " intervals)\n";
    Progress progress;
    double done = 0;
    const double steps = static_cast<double>(methods.size() + 1);
    for (const auto& m : methods) {
      const SpectrumParams p = params_of(m);
      Spectrum s;
      {
        const auto start = std::chrono::steady_clock::now();
        const EstimatedProgress ticker(progress, m, done / steps, (done + 1) / steps, each);
        s = vibration_spectrum(p);
        each = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
      ++done;
      if (meta.find("omega_ratio") == meta.end()) meta["omega_ratio"] = finite_or_null(s.omega_ratio);
      spectra[m] = finite_or_null(s.omega_ratio);
      imag[m] = s.max_imag_relative;
      if (s.negative > 0)
        warnings.push_back(detail::concat(m, ": ", s.negative, " eigenvalue(s) of -K with negative real part (unstable modes, "
                                             "omega_ratio null)"));
      if (s.max_imag_relative > 1e-8)
        warnings.push_back(detail::concat(m, ": complex eigenvalues, max |Im|/|lambda| = ", s.max_imag_relative,
                                          " (sorted by real part)"));
      add_rows(m, s.omega_ratio);
    }
    Spectrum fem;
    {
      const EstimatedProgress ticker(progress, "fem-lumped", done / steps, 1.0, each);
      fem = fem_lumped_spectrum(a->n);
    }
    add_rows("fem-lumped", fem.omega_ratio);
    meta["fem_ratio"] = finite_or_null(fem.omega_ratio);
    meta["spectra"] = spectra;
    meta["max_imag_relative"] = imag;
    meta["n"] = a->n;
    meta["unknowns"] = a->n - 1;
    meta["kernel"] = a->kernel;
    meta["h_factor"] = a->h_factor;
    meta["cloud"] = a->cloud;
    meta["warnings"] = warnings;
    for (const auto& w : warnings) std::cerr << "vrsph: warning: " << w << '\n';
    emit(t, a->out, meta.dump(), "n_over_N", "omega_ratio", "method",
         "normalised spectrum, " + std::to_string(a->n - 1) + " unknowns", false);
  });
}

}  // namespace vrsph::cli
