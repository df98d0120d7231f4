// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/aar/nested.hpp>
#include <vrsph/methods/taylor/local_system.hpp>
#include <vrsph/stencil/algebra.hpp>

namespace vrsph {

namespace {

using taylor::SmallMatrix;
using taylor::SmallVector;

class NestedKernelMethod final : public Method {
 public:
  /// correction_degree: 0 = plain kernel (original SPH), 1 or 2 = RKPM order.
  NestedKernelMethod(MethodInfo info, int correction_degree, const MethodOptions& o)
      : info_(std::move(info)), degree_(correction_degree),
        volume_(o.get_choice("volume", "dx", {"dx", "shepard"})) {
    if (degree_ > 0) policy_ = taylor::read_singular_policy(o);
  }
  const MethodInfo& info() const override { return info_; }
  // Shepard volumes sum each neighbour's own list: one more ring of particles than the rows
  // (a rank's halo, a periodic box's images; with one ring the halo's last volumes were short).
  int reach() const override { return info().stencil_rings + (volume_ == "shepard" ? 1 : 0); }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req);
    const auto& cloud = disc.cloud;
    const Index n = cloud.size();
    const bool second = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;
    if (!second) return first_order(disc, req);
    // D_a must be known at every particle a requested row reaches (boundary included, Q4).
    std::vector<char> wanted(static_cast<std::size_t>(n), 0), inner(static_cast<std::size_t>(n), 0);
    for (Index i = 0; i < n; ++i) {
      if (!taylor::wants_row(cloud, req, i)) continue;
      wanted[static_cast<std::size_t>(i)] = 1;
      inner[static_cast<std::size_t>(i)] = 1;
      for (Index j : disc.neighbours.of(i)) inner[static_cast<std::size_t>(j)] = 1;
    }
    StencilRequest greq;
    greq.kind = OperatorKind::Gradient;
    greq.rows = inner;
    const Stencil g = first_order(disc, greq);
    Stencil s = nested_second_derivative(g, req.kind == OperatorKind::DivAGrad ? req.coefficient : nullptr, wanted,
                                         req.kind);
    s.condition = g.condition;
    s.local_failure = g.local_failure;
    return s;
  }

 private:
  // Value / first derivatives with the (corrected) kernel: g_ij = -v_j grad_x K_i(x_j).
  Stencil first_order(const Discretisation& disc, const StencilRequest& req) const {
    const auto& cloud = disc.cloud;
    const int dim = cloud.dim;
    const auto v = taylor::method_volumes(disc, volume_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, dim, info_.name);
    const auto basis = taylor::multi_indices(dim, std::max(degree_, 1), true);
    const auto m = degree_ > 0 ? static_cast<Eigen::Index>(basis.size()) : 0;
    if (degree_ > 0) s.condition.assign(static_cast<std::size_t>(cloud.size()), 0);
    const int axis = req.kind == OperatorKind::Dy ? 1 : req.kind == OperatorKind::Dz ? 2 : 0;
#pragma omp parallel
    {
      SmallMatrix M(m, m), Minv(m, m);
      SmallVector c(m);
#pragma omp for schedule(dynamic, 128)
      for (Index i = 0; i < cloud.size(); ++i) {
        if (!taylor::wants_row(cloud, req, i)) continue;
        const Kernel ker = disc.kernel_at(i);
        const auto nbr = disc.neighbours.of(i);
        const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
        if (degree_ > 0) {
          // Moment system sum_j v_j W_ij p_j p_j^T c = e_1 (self included).
          M.setZero(m, m);
          for (std::size_t k = 0; k <= nbr.size(); ++k) {
            const Index j = k < nbr.size() ? nbr[k] : i;
            const Vec3 xji = cloud.positions[static_cast<std::size_t>(j)] - xi;
            const Real w = v[static_cast<std::size_t>(j)] * ker.W(xji.norm());
            SmallVector p(m);
            for (Eigen::Index a = 0; a < m; ++a) p[a] = taylor::monomial(xji, basis[static_cast<std::size_t>(a)], false);
            M.noalias() += w * p * p.transpose();
          }
          const Real cond = taylor::equilibrated_inverse(M, Minv);
          s.condition[static_cast<std::size_t>(i)] = cond;
          if (!std::isfinite(cond)) continue;
          c = Minv.col(0);
        }
        for (std::size_t k = 0; k <= nbr.size(); ++k) {
          const bool self = k == nbr.size();
          const Index j = self ? i : nbr[k];
          if (self && req.kind != OperatorKind::Value) continue;
          const Vec3 xji = cloud.positions[static_cast<std::size_t>(j)] - xi;
          const Real r = xji.norm();
          const Real W = ker.W(r);
          const Vec3 dW = ker.dW_over_r(r) * xji;  // grad_x W(x - x_i) at x_j
          Real C = 1;
          Vec3 dC = Vec3::Zero();
          if (degree_ > 0) {
            C = 0;
            for (Eigen::Index a = 0; a < m; ++a) {
              const auto& al = basis[static_cast<std::size_t>(a)];
              C += c[a] * taylor::monomial(xji, al, false);
              for (int q = 0; q < dim; ++q) dC[q] += c[a] * taylor::monomial_derivative(xji, al, q, false);
            }
          }
          const Real vj = v[static_cast<std::size_t>(j)];
          const auto slot =
              static_cast<std::size_t>(self ? s.diag[static_cast<std::size_t>(i)] : neighbour_slot(s, i, static_cast<Index>(k)));
          if (req.kind == OperatorKind::Value) {
            s.values[0][slot] = vj * C * W;
            continue;
          }
          const Vec3 gk = -vj * (dC * W + C * dW);  // weight of (u_j - u_i)
          if (req.kind == OperatorKind::Gradient)
            for (int q = 0; q < dim; ++q) s.values[static_cast<std::size_t>(q)][slot] = gk[q];
          else
            s.values[0][slot] = gk[axis];
        }
      }
    }
    if (req.kind != OperatorKind::Value) set_difference_diagonal(s);
    if (degree_ > 0) taylor::enforce_condition(s, policy_, cloud);
    return s;
  }

  MethodInfo info_;
  int degree_;
  std::string volume_;
  taylor::SingularPolicy policy_;
};

MethodInfo with_rings(MethodInfo info) {
  info.stencil_rings = 2;
  return info;
}

}  // namespace

MethodInfo aar_sph_info() {
  return with_rings({"aar-sph",
                     "[AAR] (11)-(12)",
                     "original SPH as in [AAR]: kernel first derivative, second derivative by applying it twice",
                     "O(h^2) inside; not convergent at the boundary (derivative test order -1; rod: apparent order "
                     "1 decaying; spectrum strongly underestimated)",
                     taylor::every_operator(),
                     taylor::corrected_method_options(false)});
}
MethodInfo rkpm1_info() {
  return with_rings({"rkpm1",
                     "[AAR] (21)-(26)",
                     "first-order RKPM: kernel corrected by a linear polynomial per particle, D2 = D D",
                     "as original SPH: O(h^2) inside, not convergent at the boundary",
                     taylor::every_operator(),
                     taylor::corrected_method_options(true)});
}
MethodInfo rkpm2_info() {
  return with_rings({"rkpm2",
                     "[AAR] (21)-(26)",
                     "second-order RKPM: kernel corrected by a quadratic polynomial per particle, D2 = D D",
                     "O(h^2) inside, not convergent at the boundary",
                     taylor::every_operator(),
                     taylor::corrected_method_options(true)});
}

std::unique_ptr<Method> make_aar_sph(const MethodOptions& o) {
  return std::make_unique<NestedKernelMethod>(aar_sph_info(), 0, o);
}
std::unique_ptr<Method> make_rkpm1(const MethodOptions& o) {
  return std::make_unique<NestedKernelMethod>(rkpm1_info(), 1, o);
}
std::unique_ptr<Method> make_rkpm2(const MethodOptions& o) {
  return std::make_unique<NestedKernelMethod>(rkpm2_info(), 2, o);
}

}  // namespace vrsph
