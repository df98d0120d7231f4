// SPDX-License-Identifier: BSD-3-Clause
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/operator_kind.hpp>

namespace vrsph {

const std::vector<OperatorTraits>& operator_catalogue() {
  static const std::vector<OperatorTraits> list = {
      {OperatorKind::Value, "value", 0, false},       {OperatorKind::Dx, "dx", 1, false},
      {OperatorKind::Dy, "dy", 1, false},             {OperatorKind::Dz, "dz", 1, false},
      {OperatorKind::Gradient, "gradient", 1, true},  {OperatorKind::Laplacian, "laplacian", 2, false},
      {OperatorKind::DivAGrad, "div-a-grad", 2, false},
      {OperatorKind::Hessian, "hessian", 2, true},
  };
  return list;
}

const OperatorTraits& traits(OperatorKind kind) {
  for (const auto& t : operator_catalogue())
    if (t.kind == kind) return t;
  throw ConfigError("unknown operator kind");
}

std::string_view to_string(OperatorKind kind) { return traits(kind).name; }

OperatorKind parse_operator(std::string_view name) {
  if (name == "first-derivative") return OperatorKind::Dx;
  if (name == "second-derivative") return OperatorKind::Laplacian;
  std::string known;
  for (const auto& t : operator_catalogue()) {
    if (t.name == name) return t.kind;
    known += std::string(t.name) + ", ";
  }
  throw ConfigError("unknown operator '" + std::string(name) + "' (known: " + known +
                    "first-derivative, second-derivative; on vector fields: divergence, curl, vector-laplacian, grad-div, "
                    "grad-div-composed)");
}

int components(OperatorKind kind, int dim) {
  if (kind == OperatorKind::Hessian) return dim * (dim + 1) / 2;
  return traits(kind).vector_valued ? dim : 1;
}

int hessian_component(int b, int c, int dim) {
  if (b > c) std::swap(b, c);
  // Rows b' < b hold dim - b' components each: xx, xy, xz | yy, yz | zz.
  return b * dim - b * (b - 1) / 2 + (c - b);
}

std::pair<int, int> hessian_axes(int component, int dim) {
  for (int b = 0; b < dim; ++b)
    for (int c = b; c < dim; ++c)
      if (hessian_component(b, c, dim) == component) return {b, c};
  throw ConfigError(detail::concat("the Hessian in ", dim, "D has no component ", component));
}

}  // namespace vrsph
