// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Options shared by `vrsph study` and `vrsph solve` (built-in clouds and --cloud-file).
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>
#include <vrsph/io/vtu.hpp>
#include <vrsph/solve/solver.hpp>
#include "../cli_common.hpp"

namespace vrsph::cli {

struct StudyArgs {
  std::string problem = "qw-ex5", methods = "vrsph", cloud = "uniform", n = "20,40,80,160", seeds, kernel = "cubic",
              solver = "auto", petsc_options, on_infeasible = "warn", u, a, f, g, vtu;  // vtu: written only when asked (--vtu)
  int dim = 2, h_knn = 0;
  std::string h_mode = "fixed";
  std::uint64_t seed = 1;
  double h_factor = 3, delta = 0.5, infeasible_tol = 1e-6, regular_layer = 0;
  bool perturb_boundary = false, fix_constant = false, monitor = false;
  std::string vtu_format = "binary";
  std::string neumann, q, mobility, layout, robin, beta, periodic;
  std::vector<std::string> method_opts;
  OutputOptions out;
  // Set by the user (else the problem's default applies, see problem_defaults.hpp).
  CLI::Option *dim_opt = nullptr, *kernel_opt = nullptr, *h_factor_opt = nullptr, *delta_opt = nullptr,
              *h_knn_opt = nullptr, *problem_opt = nullptr, *layout_opt = nullptr;
};

/// The linear solver settings of --solver, --petsc-options and --monitor (which prints
/// each iteration's residual to stderr).
SolverOptions solver_options(const StudyArgs& a);

/// Warnings of the runs on stderr: the infeasible-particle ones summarised (they are
/// expected on perturbed clouds), every other kind once each.
/// One line per kind of condition on stderr; `listed`: --verbose prints the rows (say so).
void print_warnings(const std::vector<std::string>& warnings, bool listed = true);
/// The one-row table of `vrsph solve` in its format; JSON adds the row's warnings and
/// infeasible particles as lists, Markdown/CSV a count of warnings.
std::string solve_summary(Table table, const std::string& format, const std::vector<std::string>& warnings,
                          const std::vector<Index>& infeasible);
/// With --verbose: every listed row, its residual and position (particle numbers of `cloud`;
/// positions only where the number is one of its particles).
void print_infeasible_rows(const std::string& label, const PointCloud& cloud, const std::vector<Index>& particles,
                           const std::vector<Real>& residuals);

/// Draws u (and its error, when the exact solution is given) over the cloud into png
/// (share/plot_field.py).
void plot_solution(const PointCloud& cloud, const Field& u, const Field* exact, const std::string& png,
                   const std::string& title);

/// --vtu-format: binary (default) or ascii.
VtuFormat parse_vtu_format(const std::string& s);

/// --cloud-file options (solve) and --cloud-file-pattern (study).
struct CloudFileArgs {
  std::string path, pattern, csv;
  double h = 0;
  // --geometry: a polygon or closed surface filled at --spacing (a list in study) instead
  // of a cloud file; --fill, --neumann-where / --dirichlet-where as `vrsph cloud`'s.
  std::string geometry, spacing, fill = "uniform", neumann_where, dirichlet_where;
  // Extra columns of the file used as per-particle values (--u-column ...), and as the
  // particle volumes weighting the L2 error (--volume-column).
  std::string u_column, a_column, f_column, g_column, q_column, volume_column;
  // --periodic on a cloud file: the box whose faces wrap (default the unit box).
  std::string box;
};

/// Adds --geometry, --spacing, --fill, --neumann-where and --dirichlet-where (a list of
/// spacings when `study`).
void add_geometry_options(CLI::App* cmd, CloudFileArgs& file, bool study);

/// Adds --u-column, --a-column, --f-column, --g-column, --q-column and --volume-column.
void add_column_options(CLI::App* cmd, CloudFileArgs& file, const std::string& file_option);
/// Refuses the column options without a cloud file (they would be silently ignored).
void reject_column_options(const CLI::App& cmd, const std::string& file_option);

/// `vrsph solve --cloud-file`: one solve on the user's cloud.
void solve_cloud_file(const StudyArgs& a, const CloudFileArgs& file, const CLI::App& cmd);
/// `vrsph study --cloud-file-pattern "c_{n}.csv" --n 16,32,64`: a refinement study over user clouds.
void study_cloud_files(const StudyArgs& a, const CloudFileArgs& file, const CLI::App& cmd);

}  // namespace vrsph::cli
