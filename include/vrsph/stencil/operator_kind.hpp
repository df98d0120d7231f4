// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The operators a stencil can approximate, with a traits table (Compadre's
// TargetOperation idea): output components, derivative order, CLI name.
#include <string_view>
#include <utility>
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
  Hessian,    ///< the second derivatives d_b d_c u, b <= c: d(d+1)/2 components sharing one pattern
              ///< (2D: xx, xy, yy; 3D: xx, xy, xz, yy, yz, zz); built for every method by
              ///< hessian_rows (methods/hessian_rows.hpp), not by the methods themselves
};

struct OperatorTraits {
  OperatorKind kind;
  std::string_view name;  ///< CLI name
  int derivative_order;   ///< 0, 1 or 2
  bool vector_valued;     ///< Gradient: dim components; Hessian: dim (dim + 1) / 2
};

const std::vector<OperatorTraits>& operator_catalogue();
const OperatorTraits& traits(OperatorKind kind);
std::string_view to_string(OperatorKind kind);
/// Accepts the catalogue names and the 1D aliases "first-derivative" (= dx) and
/// "second-derivative" (= laplacian). Throws ConfigError naming the known ones.
OperatorKind parse_operator(std::string_view name);
/// Number of stored value arrays for this operator in dimension dim.
int components(OperatorKind kind, int dim);
/// The Hessian's component holding d_b d_c (either order), and the axes (b <= c) of component k.
int hessian_component(int b, int c, int dim);
std::pair<int, int> hessian_axes(int component, int dim);

}  // namespace vrsph
