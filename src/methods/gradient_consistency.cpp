// SPDX-License-Identifier: BSD-3-Clause
#include "cubic_rows.hpp"
#include <vrsph/core/error.hpp>
#include <vrsph/methods/gradient_consistency.hpp>

namespace vrsph {

namespace {

// The component arrays of `s` and the axis each differentiates.
std::vector<std::pair<std::size_t, int>> components_and_axes(OperatorKind kind, int dim) {
  switch (kind) {
    case OperatorKind::Gradient: {
      std::vector<std::pair<std::size_t, int>> out;
      for (int c = 0; c < dim; ++c) out.emplace_back(static_cast<std::size_t>(c), c);
      return out;
    }
    case OperatorKind::Dx: return {{0, 0}};
    case OperatorKind::Dy: return {{0, 1}};
    case OperatorKind::Dz: return {{0, 2}};
    default: break;
  }
  throw ConfigError("cubic exactness applies to first-derivative stencils (gradient, dx, dy, dz)");
}

}  // namespace

GradientConsistencyReport raise_to_cubic_exactness(const Discretisation& disc, const StencilRequest& req, Stencil& s,
                                                   Real max_condition) {
  const int dim = disc.cloud.dim;
  std::vector<cubic_rows::Target> targets;
  for (const auto& [array, axis] : components_and_axes(s.kind, dim)) {
    check<ConfigError>(axis < dim, "cubic exactness: a derivative along axis ", axis, " in ", dim, "D");
    std::array<int, 3> alpha{};
    alpha[static_cast<std::size_t>(axis)] = 1;  // the derivative of x_axis along axis is 1/h in scaled variables
    targets.push_back({array, cubic_rows::monomial_index(dim, alpha), 1, 1});
  }
  cubic_rows::Outcome o;
  switch (dim) {
    case 1: o = cubic_rows::correct_rows<3, 1>(disc, req, s, targets, max_condition); break;
    case 2: o = cubic_rows::correct_rows<9, 2>(disc, req, s, targets, max_condition); break;
    default: o = cubic_rows::correct_rows<19, 3>(disc, req, s, targets, max_condition); break;
  }
  return {o.corrected, std::move(o.kept)};
}

}  // namespace vrsph
