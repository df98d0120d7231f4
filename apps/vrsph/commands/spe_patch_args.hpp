// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Options of `vrsph operator --problem spe-patch` ([SPE] §4 operator tests).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>
#include "../cli_common.hpp"

namespace vrsph::cli {

struct SpePatchArgs {
  std::string test = "power-sum", profile;
  int exponent = 3;
  bool rotated = false;
  std::vector<std::string> variants;
};

void add_spe_patch_options(CLI::App* cmd, SpePatchArgs& a);
/// Runs the patch test with the operator command's --dim, --h-factor (= f), --delta, --seed
/// and output options; refuses the options that do not apply.
void run_spe_patch_command(const SpePatchArgs& a, const CLI::App& cmd, int dim, double h_factor, double delta,
                           std::uint64_t seed, const OutputOptions& out);

}  // namespace vrsph::cli
