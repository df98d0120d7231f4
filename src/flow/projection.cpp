// SPDX-License-Identifier: BSD-3-Clause
// The approximate projection and the advection term from a method's operators (projection.hpp).
#include <vrsph/core/error.hpp>
#include <vrsph/flow/projection.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

CsrMatrix laplacian_matrix(const Operators& ops) {
  const Stencil& L = ops.stencil(OperatorKind::Laplacian);
  require_point_rows(L, "a projection");
  return CsrMatrix(as_eigen(L));
}

Projected project(const Operators& ops, const PressurePoisson& ppe, const Eigen::MatrixXd& w, const Field& phi_guess) {
  const int d = ops.cloud().dim;
  check<InputError>(w.rows() == ops.cloud().size() && w.cols() == d, "projection: a velocity of ", w.rows(), " x ",
                    w.cols(), " for ", ops.cloud().size(), " particles in ", d, "D");
  Projected out;
  const Field div = ops.apply(VectorOperator::Divergence, w).col(0);
  out.phi = phi_guess;
  const PressurePoisson::Result r = ppe.solve(div, out.phi);
  out.shift = r.shift;
  out.report = r.report;
  out.u = w - ops.apply(OperatorKind::Gradient, out.phi);
  return out;
}

Eigen::MatrixXd advection(const Operators& ops, const Eigen::MatrixXd& u) {
  const auto n = u.rows();
  const int d = static_cast<int>(u.cols());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, d);
  for (int c = 0; c < d; ++c) {
    const Eigen::MatrixXd g = ops.apply(OperatorKind::Gradient, Field(u.col(c)));  // N x d: ∂u_c/∂x_k
    a.col(c) = (u.array() * g.array()).rowwise().sum().matrix();
  }
  return a;
}

}  // namespace vrsph
