// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The operators a stencil can approximate, with a traits table (Compadre's
// TargetOperation idea): output components, derivative order, CLI name.
#include <string_view>
#include <vector>

namespace vrsph {

enum class OperatorKind {
  Value,      ///< interpolation <u>_i (not exact on constants for plain SPH)
  Dx,         ///< du/dx (also the 1D first derivative)
  Dy,         ///< du/dy
  Dz,         ///< du/dz
  Gradient,   ///< grad u: d components sharing one sparsity pattern
  Laplacian,  ///< div grad u (also the 1D second derivative)
  DivAGrad,   ///< div(a grad u) for a scalar coefficient a(x) > 0
};

struct OperatorTraits {
  OperatorKind kind;
  std::string_view name;  ///< CLI name
  int derivative_order;   ///< 0, 1 or 2
  bool vector_valued;     ///< Gradient: dim components
};

const std::vector<OperatorTraits>& operator_catalogue();
const OperatorTraits& traits(OperatorKind kind);
std::string_view to_string(OperatorKind kind);
/// Accepts the catalogue names and the 1D aliases "first-derivative" (= dx) and
/// "second-derivative" (= laplacian). Throws ConfigError naming the known ones.
OperatorKind parse_operator(std::string_view name);
/// Number of stored value arrays for this operator in dimension dim.
int components(OperatorKind kind, int dim);

}  // namespace vrsph
