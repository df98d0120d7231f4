// SPDX-License-Identifier: BSD-3-Clause
// `vrsph spectrum`: [AAR]'s vibration test, normalised spectra of methods beside lumped FEM.
#include <chrono>
#include <cmath>
#include <iostream>
#include <vrsph/io/json.hpp>
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


SpectrumParams spectrum_params(const SpectrumArgs& a, const std::string& method, const MethodOptions& options,
                               CloudFamily family) {
  SpectrumParams p;
  p.method = method;
  p.options = options;
  p.n = a.n;
  p.kernel = parse_kernel(a.kernel);
  p.h_factor = a.h_factor;
  p.cloud = family;
  p.delta = a.delta;
  p.seed = a.seed;
  return p;
}

// Dense O(n^3) eigenproblems: refuse what does not fit, say how long the rest takes. A long
// run is timed first on a quarter of the intervals (a 64th of one problem's work); the
// caller re-times each problem as it finishes, so the progress bar and the estimate follow
// this machine's speed now, not a fixed rate. Returns the seconds per problem.
double seconds_per_spectrum(const SpectrumArgs& a, const SpectrumParams& first, std::size_t problems) {
  check_spectrum_size(a.n);
  double each = dense_spectrum_seconds(a.n);
  if (each * static_cast<double>(problems) > 2) each = calibrated_spectrum_seconds(first);
  const double total = each * static_cast<double>(problems);
  if (total > 10)
    std::cerr << "vrsph: spectrum: " << problems << " dense eigenvalue problems of " << a.n - 1 << " unknowns, about "
              << static_cast<long long>(std::ceil(total)) << " s in all (O(n^3), timed on " << std::max(3, a.n / 4)
              << " intervals)\n";
  return each;
}

void add_spectrum_rows(Table& t, const std::string& name, const std::vector<Real>& ratio) {
  for (std::size_t k = 0; k < ratio.size(); ++k)
    t.add_row({{"method", name},
               {"mode", static_cast<long long>(k + 1)},
               {"n_over_N", static_cast<Real>(k + 1) / static_cast<Real>(ratio.size())},
               {"omega_ratio", ratio[k]}});
}

// What a spectrum says a user should know: unstable modes, complex eigenvalues.
void collect_spectrum_warnings(const std::string& m, const Spectrum& s, std::vector<std::string>& warnings) {
  if (s.negative > 0)
    warnings.push_back(detail::concat(m, ": ", s.negative, " eigenvalue(s) of -K with negative real part (unstable modes, "
                                         "omega_ratio null)"));
  if (s.max_imag_relative > 1e-8)
    warnings.push_back(detail::concat(m, ": complex eigenvalues, max |Im|/|lambda| = ", s.max_imag_relative,
                                      " (sorted by real part)"));
}

void run_spectrum(const SpectrumArgs& a) {
  validate_output(a.out);
  const auto methods = parse_name_list(a.methods, "--method");
  const auto options = parse_method_options(a.method_opts, methods);
  note_row_forms(methods, options, StencilUse::Values);
  const CloudFamily family = parse_cloud_family(a.cloud);
  check<ConfigError>(family == CloudFamily::Uniform || family == CloudFamily::Perturbed,
                     "vrsph spectrum: --cloud must be uniform or perturbed");
  Table t;
  t.columns = {"method", "mode", "n_over_N", "omega_ratio"};
  Json meta, spectra = Json::object(), imag = Json::object();
  std::vector<std::string> warnings;
  const auto params_of = [&](const std::string& m) { return spectrum_params(a, m, options_for(options, m), family); };
  double each = seconds_per_spectrum(a, params_of(methods.front()), methods.size() + 1);
  Progress progress;
  double done = 0;
  const double steps = static_cast<double>(methods.size() + 1);
  for (const auto& m : methods) {
    Spectrum s;
    {
      const auto start = std::chrono::steady_clock::now();
      const EstimatedProgress ticker(progress, m, done / steps, (done + 1) / steps, each);
      s = vibration_spectrum(params_of(m));
      each = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    ++done;
    if (!meta.contains("omega_ratio")) meta["omega_ratio"] = Json(s.omega_ratio);  // not finite: null
    spectra[m] = Json(s.omega_ratio);
    imag[m] = s.max_imag_relative;
    collect_spectrum_warnings(m, s, warnings);
    add_spectrum_rows(t, m, s.omega_ratio);
  }
  Spectrum fem;
  {
    const EstimatedProgress ticker(progress, "fem-lumped", done / steps, 1.0, each);
    fem = fem_lumped_spectrum(a.n);
  }
  add_spectrum_rows(t, "fem-lumped", fem.omega_ratio);
  meta["fem_ratio"] = Json(fem.omega_ratio);
  meta["spectra"] = spectra;
  meta["max_imag_relative"] = imag;
  meta["n"] = a.n;
  meta["unknowns"] = a.n - 1;
  meta["kernel"] = a.kernel;
  meta["h_factor"] = a.h_factor;
  meta["cloud"] = a.cloud;
  meta["warnings"] = warnings;
  for (const auto& w : warnings) std::cerr << "vrsph: warning: " << w << '\n';
  emit(t, a.out, meta, "n_over_N", "omega_ratio", "method",
       "normalised spectrum, " + std::to_string(a.n - 1) + " unknowns", false);
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
  cmd->callback([a] { run_spectrum(*a); });
}

}  // namespace vrsph::cli
