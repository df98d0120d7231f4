// SPDX-License-Identifier: BSD-3-Clause
// `vrsph operator --problem spe-patch`: the [SPE] §4 operator tests (Figs. 1–4) as a summary
// table, the cross-section profile (--profile FILE.csv) and a PNG of the profile (--plot).
#include <vrsph/reproduce/spe_patch.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include "../cli_common.hpp"
#include "spe_patch_args.hpp"

namespace vrsph::cli {

namespace {
// The variants of the paper's figure for each test.
std::vector<std::string> default_variants(const std::string& test) {
  if (test == "r2")  // Figs. 1–2: Brookshaw with ∇W and ∇*W, CB-SPH; Schwaiger with ∇W and ∇*W
    return {"brookshaw", "brookshaw:pair_gradient=corrected", "cb-sph", "s-sph", "s-sph:pair_gradient=corrected"};
  std::vector<std::string> v;  // Figs. 3–4: CB, S, M x the four kernel gradients
  for (const char* m : {"cb-sph", "s-sph", "m-sph"})
    for (const char* g : {"g1", "g2", "g3", "g4"}) v.push_back(std::string(m) + ":gradient=" + g);
  return v;
}
}  // namespace

void add_spe_patch_options(CLI::App* cmd, SpePatchArgs& a) {
  cmd->add_option("--test", a.test,
                  "spe-patch: r2 (Figs. 1-2), power-sum (Fig. 3, u = sum x_k^s), product ((xy)^s) or heterogeneous "
                  "(Fig. 4, div((x+y) grad u_s))")
      ->capture_default_str();
  cmd->add_option("--exponent", a.exponent, "spe-patch: the exponent s (Fig. 3: 3; Fig. 4: 1)")->capture_default_str();
  cmd->add_flag("--rotated", a.rotated, "spe-patch: the lattice turned by 45 degrees (off-diagonal terms)");
  cmd->add_option("--variant", a.variants,
                  "spe-patch: a scheme with options, method[:key=value,...] (repeatable; default: the figure's schemes)");
  cmd->add_option("--profile", a.profile, "spe-patch: write the cross-section profile (variant, x, value, exact, error) "
                                          "to this CSV file");
}

void run_spe_patch_command(const SpePatchArgs& a, const CLI::App& cmd, int dim, double h_factor, double delta,
                           std::uint64_t seed, const OutputOptions& out) {
  for (const char* opt : {"--method", "--method-opt", "--operator", "--cloud", "--n", "--kernel", "--u", "--exact", "--a",
                          "--no-ghosts", "--h-mode", "--h-knn", "--regular-layer"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply to --problem spe-patch (use --test, --exponent, "
                                             "--variant, --h-factor as f, --delta)");
  SpePatchParams p;
  p.test = a.test;
  p.exponent = a.exponent;
  p.dim = dim;
  p.rotated = a.rotated;
  p.f = cmd.count("--h-factor") ? h_factor : 0;
  p.delta = cmd.count("--delta") ? delta : 0;
  p.seed = seed;
  for (const auto& v : a.variants.empty() ? default_variants(a.test) : a.variants) p.variants.push_back(parse_patch_variant(v));
  const SpePatchResult r = run_spe_patch(p);
  const Table profile = profile_table(r);
  if (!a.profile.empty())
    write_file(a.profile, "profile file", [&](std::ostream& f) { f << format_table(profile, TableFormat::Csv); });
  const std::string title = "spe-patch " + a.test + (a.test == "r2" ? "" : " s=" + std::to_string(a.exponent)) +
                            (a.rotated ? " rotated" : "") + " " + std::to_string(dim) + "D";
  OutputOptions no_plot = out;
  no_plot.plot.clear();
  emit(summary_table(r), no_plot, Json::object({{"problem", "spe-patch"}, {"test", a.test}}), "", "", "", "");
  if (!out.plot.empty()) plot_table(profile, Json(), out.plot, "x", "value", "variant", title, false);
}

}  // namespace vrsph::cli
