// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Truncation-error study of operator stencils: method x operator x cloud family x
// refinement list -> errors and observed orders. Shared by `vrsph operator` and the
// convergence tests, so both run exactly the same code.
//
// Problems:
//   qw-trunc  [QW] Examples 1, 2, 4: f = cos(pi x) cos(pi y) [cos(pi x) in 1D,
//             product over 3 coordinates in 3D] on [-1,1]^d, dx = 2/n. With ghosts
//             (default): cell-centred lattice continued over a layer of width h + dx so
//             no kernel is truncated; errors over the particles inside the domain.
//             Without ghosts ([QW] Example 4): layout A (vertex lattice with boundary
//             particles), errors over the particles of the open domain (METHODS P14).
//   unit-box  the same constructions on [0,1]^d (for user expressions).
//   aar-derivative  [AAR] §5 derivative test: f = e^x on
//             [0,1], layout x_j = (j-1)/n, no ghosts, error at every particle (ends
//             included); defaults Gaussian l = dx, U(-dx/4, dx/4) (problem_defaults.hpp).
#include <functional>
#include <map>
#include <string>
#include <optional>
#include <vrsph/stencil/vector_operators.hpp>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/stencil/operator_kind.hpp>

namespace vrsph {

struct OperatorStudyParams {
  std::string problem = "qw-trunc";
  int dim = 2;
  std::vector<std::string> methods{"sph"};
  std::map<std::string, MethodOptions> method_options;  ///< per method name
  OperatorKind op = OperatorKind::Laplacian;
  CloudFamily cloud = CloudFamily::Uniform;
  std::vector<int> n{8, 16, 32, 64, 128};
  std::uint64_t seed = 1;
  Real h_factor = 3;  ///< kappa: support radius h = kappa * dx (see h_mode)
  SmoothingMode h_mode = SmoothingMode::Fixed;
  int h_knn = 0;
  Real delta = 0.5;
  bool ghosts = true;
  /// Periodic axes of the problem's box ("x,y", "all"; empty: none): no boundary and no ghost
  /// particles along them, the stencils built by periodic_stencil (h-mode fixed).
  std::string periodic;
  /// A vector operator (divergence, curl, vector Laplacian) in place of `op`: u is then d
  /// comma-separated expressions (one per component) and op is the stencil it is made from
  /// (base_operator); --exact has output_components expressions.
  std::optional<VectorOperator> vector_op;
  bool evaluate_boundary = false;  ///< errors also at boundary particles (always for aar-derivative)
  Real regular_layer = 0;  ///< see PerturbOptions::regular_layer
  KernelType kernel = KernelType::CubicSpline;
  std::string u;        ///< function name from the catalogue or a muParser expression; empty: problem default
  std::string exact;    ///< optional expected operator value(s), ';'-separated for the gradient
  std::string a;        ///< coefficient for div-a-grad (catalogue name or expression); empty: "one-plus-r2"
  /// Called after each (method, n) step with a label and the fraction done.
  std::function<void(const std::string&, double)> progress;
};

struct OperatorStudyRow {
  std::string method;
  int n = 0;
  Index particles = 0;    ///< particles inside the domain (ghosts excluded)
  Index total = 0;        ///< including ghosts
  Real dx = 0, h = 0;
  ErrorReport errors;
  Real order_inf = 0, order_l2 = 0;  ///< pairwise, NaN in the first row of a method
  Real neighbours_mean = 0;
  Index neighbours_min = 0, neighbours_max = 0;
  Real nnz_per_row = 0;
  Real max_local_residual = 0;  ///< max over evaluated rows of the method's local residual / sqrt(d)
  Index infeasible = 0;         ///< evaluated rows with local residual / sqrt(d) > 1e-6 (or failed local solve)
  Index signed_rows = 0;        ///< evaluated rows that took negative volumes (VRSPH boundary=signed)
  Real condition_max = 0;       ///< largest local-system condition number over evaluated rows (0: none)
  Real seconds_cloud = 0, seconds_neighbours = 0, seconds_stencil = 0, seconds_apply = 0;
};

struct OperatorStudyResult {
  OperatorStudyParams params;
  std::vector<OperatorStudyRow> rows;
  std::map<std::string, Real> fitted_order_inf;  ///< least-squares slope per method
};

/// Throws ConfigError/InputError for bad parameters before any work is done.
OperatorStudyResult run_operator_study(const OperatorStudyParams& params);
Table to_table(const OperatorStudyResult& result);
/// Problem/parameter metadata as a JSON object (merged into --format json output).
Json metadata_json(const OperatorStudyResult& result);

}  // namespace vrsph
