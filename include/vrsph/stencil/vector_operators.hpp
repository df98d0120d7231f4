// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Operators on vector fields U (N x d, one column per component), from the stencils every
// method already builds: the divergence and the curl from its gradient rows G_c, the vector
// Laplacian from its Laplacian rows applied to each component. So a method's promises carry
// over: exact on linear fields where its gradient is, second order where its gradient and
// Laplacian are. The gradient of the divergence from Hessian rows (methods/hessian_rows.hpp).
//   div U   = sum_c G_c U_c
//   curl U  = G_x U_y - G_y U_x                       (2D: a scalar)
//           = (G_y U_z - G_z U_y, G_z U_x - G_x U_z, G_x U_y - G_y U_x)   (3D)
//   lap U   = (L U_1, ..., L U_d)
//   grad div U = (sum_c H_bc U_c)_b                    (Hessian rows exact on cubics: second order
//                in the max norm on disordered clouds)
//   grad div U = G (sum_c G_c U_c)                     (grad-div-composed: the method's gradient
//                rows applied twice; each row reads its neighbours' neighbours; consistent where G
//                is, but the max-norm order falls short of 2 on disordered clouds, docs/periodic.md)
#include <optional>
#include <string_view>
#include <vrsph/stencil/operator_kind.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

enum class VectorOperator { Divergence, Curl, VectorLaplacian, GradDiv, GradDivComposed };

/// "divergence", "curl", "vector-laplacian", "grad-div", "grad-div-composed"; nullopt for any other name.
std::optional<VectorOperator> parse_vector_operator(std::string_view name);
std::string_view to_string(VectorOperator op);
/// The stencil the operator is made from: Gradient (divergence, curl, grad-div-composed), Laplacian
/// (vector Laplacian) or Hessian (grad-div).
OperatorKind base_operator(VectorOperator op);
/// Columns of the result: 1 (divergence; curl in 2D), 3 (curl in 3D), d (vector Laplacian, grad-div
/// and grad-div-composed).
/// ConfigError for a curl in 1D.
int output_components(VectorOperator op, int dim);
/// The operator applied to U (N x dim) with `base` = the method's base_operator stencil.
/// InputError for a stencil of another kind or a U of another shape.
Eigen::MatrixXd apply_vector(VectorOperator op, const Stencil& base, const Eigen::MatrixXd& U);

}  // namespace vrsph
