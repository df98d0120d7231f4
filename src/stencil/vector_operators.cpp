// SPDX-License-Identifier: BSD-3-Clause
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

namespace {
// The divergence and the curl from the gradient rows in one pass over them, each output the
// sum or difference of only the derivatives it needs, Σ_k G_b[k] U(j_k, c) per (b, c) in row order
// and then combined as apply_vector combined whole columns (the same rounding). Applying the
// whole gradient to every component took dim² products and dim temporaries of N x dim: at 10^6
// 2D particles the divergence took about twice as long.
Eigen::MatrixXd first_derivative_combination(VectorOperator op, const Stencil& g, const Eigen::MatrixXd& U) {
  const int dim = g.dim;
  const Index n = g.rows();
  Eigen::MatrixXd out(n, output_components(op, dim));
  // ∂_b U_c of row i, the pairs (b, c) the operator reads.
  auto derivative = [&](Index i, int b, int c) { return row_product(g, b, i, U.col(c).data()); };
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    if (op == VectorOperator::Divergence) {
      Real sum = 0;
      for (int c = 0; c < dim; ++c) sum += derivative(i, c, c);
      out(i, 0) = sum;
    } else if (dim == 2) {
      out(i, 0) = derivative(i, 0, 1) - derivative(i, 1, 0);
    } else {
      out(i, 0) = derivative(i, 1, 2) - derivative(i, 2, 1);
      out(i, 1) = derivative(i, 2, 0) - derivative(i, 0, 2);
      out(i, 2) = derivative(i, 0, 1) - derivative(i, 1, 0);
    }
  }
  return out;
}
}  // namespace

Eigen::MatrixXd apply_vector(VectorOperator op, const Stencil& base, const Eigen::MatrixXd& U) {
  const int dim = base.dim;
  check<InputError>(base.kind == base_operator(op), to_string(op), " is made from a ", to_string(base_operator(op)),
                    " stencil, got a ", to_string(base.kind), " stencil");
  check<InputError>(U.rows() == base.rows() && U.cols() == dim, to_string(op), ": the field is ", U.rows(), " x ",
                    U.cols(), ", the stencil wants ", base.rows(), " x ", dim, " (one column per component)");
  if (op == VectorOperator::Divergence || op == VectorOperator::Curl) return first_derivative_combination(op, base, U);
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
  // GradDivComposed: G (div U).
  return apply(base, Field(first_derivative_combination(VectorOperator::Divergence, base, U).col(0)));
}

}  // namespace vrsph
