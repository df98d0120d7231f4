// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Problem files: `vrsph solve --config problem.toml` (and `study`). A TOML file whose keys
// are the command's long option names without the dashes; tables only group keys
// ([problem] u = "...", [solver] petsc-options = "..."). Options given on the command line
// win over the file. Values go through the same parsing and checks as command-line values.
//
//   method = "vrsph"
//   cloud-file = "annulus.csv"          # paths are relative to the problem file
//   [problem]
//   a = "1 + x^2"
//   f = "-1"
//   g = "0"
//   [output]
//   vtu = "u.vtu"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace vrsph::cli {

/// Adds --config FILE to cmd.
CLI::Option* add_config_option(CLI::App* cmd, std::string& path);

/// Sets every option of cmd named in the file that the command line left unset. Paths
/// (every option that names a file: cloud-file, geometry, perm-file, output, vtu, plot,
/// history, krylov-output, ...) are taken relative to the file's directory. Throws IoError
/// for an unreadable file and ConfigError naming file:line for a TOML error, an unknown key
/// (help and version included: a file holds settings, not actions), a value of the wrong
/// kind, or a value the option refuses.
void apply_problem_file(CLI::App& cmd, const std::string& path);

}  // namespace vrsph::cli
