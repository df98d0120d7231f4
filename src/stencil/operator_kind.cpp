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
                    "first-derivative, second-derivative; on vector fields: divergence, curl, vector-laplacian)");
}

int components(OperatorKind kind, int dim) { return traits(kind).vector_valued ? dim : 1; }

}  // namespace vrsph
