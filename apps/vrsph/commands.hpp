// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Each subcommand registers itself on the CLI11 app; the callbacks may throw
// vrsph::Error, which main() turns into a message and an exit code.
#include <CLI/CLI.hpp>

namespace vrsph::cli {

void add_methods_command(CLI::App& app);
void add_kernels_command(CLI::App& app);
void add_cloud_command(CLI::App& app);
void add_operator_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_study_command(CLI::App& app);
void add_solve_command(CLI::App& app);
void add_spectrum_command(CLI::App& app);
void add_stability_command(CLI::App& app);
void add_diffuse_command(CLI::App& app);
void add_flow_command(CLI::App& app);

}  // namespace vrsph::cli
