// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/method.hpp>

namespace vrsph {

bool MethodInfo::supports(OperatorKind k) const {
  return std::find(operators.begin(), operators.end(), k) != operators.end();
}

std::vector<OperatorKind> MethodInfo::provided() const {
  std::vector<OperatorKind> all = operators;
  if (!supports(OperatorKind::Hessian)) all.push_back(OperatorKind::Hessian);
  return all;
}

void check_request(const MethodInfo& info, const Discretisation& disc, const StencilRequest& request, bool periodic_pairs) {
  check<ConfigError>(info.supports(request.kind), "method ", info.name, " does not provide operator ",
                     to_string(request.kind));
  check<InputError>(disc.neighbours.size() == disc.cloud.size(), "neighbour list has ", disc.neighbours.size(),
                    " rows for ", disc.cloud.size(), " particles (size mismatch)");
  check<ConfigError>(periodic_pairs || disc.neighbours.shifts.empty(), "method ", info.name, ": this neighbour list crosses periodic faces "
                     "(NeighbourList::shifts) and the method reads positions: build the stencil with periodic_stencil(), "
                     "which gives it the periodic images");
  check<InputError>(request.rows.empty() || static_cast<Index>(request.rows.size()) == disc.cloud.size(),
                    "row mask has ", request.rows.size(), " entries for ", disc.cloud.size(), " particles (size mismatch)");
  if (request.kind != OperatorKind::DivAGrad) return;
  if (request.mobility) {
    check<ConfigError>(info.tensor_mobility, "method ", info.name,
                       " cannot take a tensor (diagonal anisotropic) mobility; give a scalar coefficient, or use vrsph "
                       "or one of the [SPE] schemes (brookshaw, cb-sph, s-sph, m-sph)");
    check<InputError>(request.coefficient == nullptr, "operator div-a-grad: give either a scalar coefficient or a "
                      "tensor mobility, not both");
    const Eigen::MatrixXd& m = *request.mobility;
    check<InputError>(m.rows() == disc.cloud.size() && m.cols() == disc.cloud.dim, "mobility has ", m.rows(), " x ",
                      m.cols(), " values for ", disc.cloud.size(), " particles in ", disc.cloud.dim,
                      "D (size mismatch: one value per particle and direction)");
    for (Index i = 0; i < m.rows(); ++i)
      for (Index k = 0; k < m.cols(); ++k) {
        const Vec3& x = disc.cloud.positions[static_cast<std::size_t>(i)];
        check<InputError>(std::isfinite(m(i, k)) && m(i, k) > 0, "mobility m_", k + 1, " must be positive and finite: ",
                          m(i, k), " at particle ", i, " (", x[0], ", ", x[1], ", ", x[2], ")");
      }
    return;
  }
  check<InputError>(request.coefficient != nullptr, "operator div-a-grad needs the coefficient a at every particle");
  check_scalar_coefficient(disc.cloud, *request.coefficient);
}

void check_scalar_coefficient(const PointCloud& cloud, const Field& a) {
  check<InputError>(a.size() == cloud.size(), "coefficient a has ", a.size(), " values for ", cloud.size(),
                    " particles (size mismatch)");
  for (Index i = 0; i < a.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    check<InputError>(std::isfinite(a[i]) && a[i] > 0, "coefficient a must be positive and finite: a = ", a[i],
                      " at particle ", i, " (", x[0], ", ", x[1], ", ", x[2], ")");
  }
}

Real rows_reach(const Method& method, StencilUse use, bool coefficient_gradient_given) {
  const bool estimates = !coefficient_gradient_given && method.needs_coefficient_gradient(use);
  return std::max(method.reach_for(use), estimates ? method.estimated_gradient_reach() : Real{0});
}

}  // namespace vrsph
