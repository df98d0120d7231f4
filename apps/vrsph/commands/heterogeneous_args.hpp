// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Options of the heterogeneous-media problems of `vrsph study` (spe-channel, spe-lognormal,
// spe10): the permeability field and the Krylov study.
#include <CLI/CLI.hpp>
#include <string>
#include "study_args.hpp"

namespace vrsph::cli {

/// The help group of the options below.
inline const std::string heterogeneous_group = "Heterogeneous media (spe-channel, spe-lognormal, spe10)";

struct HeterogeneousArgs {
  std::string perm_file, perm_grid = "60,220,85", perm_subset;
  double contrast = 1e6, sigma_ln = 1.5, correlation_length = 0.1, kz_ratio = 1;
  int channels = 0;
  std::string krylov, krylov_output, history, vtu;
  int restart = 30, max_iterations = 3000;
  double rtol = 1e-8;
};

/// Adds the field and Krylov options to `vrsph study` (their own help group).
void add_heterogeneous_options(CLI::App* cmd, HeterogeneousArgs& args);

/// `vrsph study --problem spe-channel|spe-lognormal|spe10 ...`: refuses the options of the
/// other problems, runs the study and prints its table(s).
void study_heterogeneous(const StudyArgs& a, const HeterogeneousArgs& h, const CLI::App& cmd);

}  // namespace vrsph::cli
