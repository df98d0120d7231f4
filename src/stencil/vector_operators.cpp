// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/stencil/vector_operators.hpp>

namespace vrsph {

std::optional<VectorOperator> parse_vector_operator(std::string_view name) {
  if (name == "divergence") return VectorOperator::Divergence;
  if (name == "curl") return VectorOperator::Curl;
  if (name == "vector-laplacian") return VectorOperator::VectorLaplacian;
  if (name == "grad-div") return VectorOperator::GradDiv;
  if (name == "grad-div-composed") return VectorOperator::GradDivComposed;
  return std::nullopt;
}

std::string_view to_string(VectorOperator op) {
  switch (op) {
    case VectorOperator::Divergence: return "divergence";
    case VectorOperator::Curl: return "curl";
    case VectorOperator::VectorLaplacian: return "vector-laplacian";
    case VectorOperator::GradDiv: return "grad-div";
    case VectorOperator::GradDivComposed: return "grad-div-composed";
  }
  return "?";
}

OperatorKind base_operator(VectorOperator op) {
  if (op == VectorOperator::VectorLaplacian) return OperatorKind::Laplacian;
  return op == VectorOperator::GradDiv ? OperatorKind::Hessian : OperatorKind::Gradient;
}

int output_components(VectorOperator op, int dim) {
  if (op == VectorOperator::Divergence) return 1;
  if (op == VectorOperator::VectorLaplacian || op == VectorOperator::GradDiv || op == VectorOperator::GradDivComposed)
    return dim;
  check<ConfigError>(dim >= 2, "the curl needs 2 or 3 dimensions, got ", dim);
  return dim == 2 ? 1 : 3;
}

Eigen::MatrixXd apply_vector(VectorOperator op, const Stencil& base, const Eigen::MatrixXd& U) {
  const int dim = base.dim;
  check<InputError>(base.kind == base_operator(op), to_string(op), " is made from a ", to_string(base_operator(op)),
                    " stencil, got a ", to_string(base.kind), " stencil");
  check<InputError>(U.rows() == base.rows() && U.cols() == dim, to_string(op), ": the field is ", U.rows(), " x ",
                    U.cols(), ", the stencil wants ", base.rows(), " x ", dim, " (one column per component)");
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(U.rows(), output_components(op, dim));
  if (op == VectorOperator::VectorLaplacian) {
    for (int c = 0; c < dim; ++c) out.col(c) = apply_component(base, Field(U.col(c)), 0);
    return out;
  }
  if (op == VectorOperator::GradDiv) {  // (grad div U)_b = Σ_c ∂_b ∂_c U_c
    for (int c = 0; c < dim; ++c) {
      const Eigen::MatrixXd h = apply(base, Field(U.col(c)));  // every ∂_a ∂_e U_c
      for (int b = 0; b < dim; ++b) out.col(b) += h.col(hessian_component(b, c, dim));
    }
    return out;
  }
  // d[c](:, b) = G_b U_c: every first derivative of every component.
  std::array<Eigen::MatrixXd, 3> d;
  for (int c = 0; c < dim; ++c) d[static_cast<std::size_t>(c)] = apply(base, Field(U.col(c)));
  if (op == VectorOperator::Divergence || op == VectorOperator::GradDivComposed) {
    for (int c = 0; c < dim; ++c) out.col(0) += d[static_cast<std::size_t>(c)].col(c);
    if (op == VectorOperator::GradDivComposed) out = apply(base, Field(out.col(0)));  // G (div U)
  } else if (dim == 2) {
    out.col(0) = d[1].col(0) - d[0].col(1);
  } else {
    out.col(0) = d[2].col(1) - d[1].col(2);
    out.col(1) = d[0].col(2) - d[2].col(0);
    out.col(2) = d[1].col(0) - d[0].col(1);
  }
  return out;
}

}  // namespace vrsph
