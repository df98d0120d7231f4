// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/aar/modified_fpm.hpp>
#include <vrsph/methods/taylor/local_system.hpp>

namespace vrsph {

namespace {

using taylor::SmallMatrix;

const std::vector<OperatorKind> operators{OperatorKind::Dx, OperatorKind::Gradient, OperatorKind::Laplacian,
                                           OperatorKind::DivAGrad};

class ModifiedFpm final : public Method {
 public:
  ModifiedFpm(MethodInfo info, bool corrected_kernel, const MethodOptions& o)
      : info_(std::move(info)), corrected_(corrected_kernel), volume_(o.get_choice("volume", "dx", {"dx", "shepard"})),
        policy_(taylor::read_singular_policy(o)) {}
  const MethodInfo& info() const override { return info_; }
  // Shepard volumes sum each neighbour's own list: one more ring of particles than the rows
  // (a rank's halo, a periodic box's images; with one ring the halo's last volumes were short).
  int reach() const override { return info().stencil_rings + (volume_ == "shepard" ? 1 : 0); }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req);
    const auto& cloud = disc.cloud;
    check<ConfigError>(cloud.dim == 1, "method ", info_.name,
                       " is defined in 1D only ([AAR]); use fpm for the 2D/3D second-order finite particle method");
    const auto v = taylor::method_volumes(disc, volume_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, 1, info_.name);
    s.condition.assign(static_cast<std::size_t>(cloud.size()), 0);
    const bool second = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;
#pragma omp parallel
    {
      std::vector<Real> K, DK;  // (corrected) kernel and its x-derivative at the neighbours
      SmallMatrix A(2, 2), Ainv(2, 2), C(3, 3), Cinv(3, 3);
#pragma omp for schedule(dynamic, 128)
      for (Index i = 0; i < cloud.size(); ++i) {
        if (!taylor::wants_row(cloud, req, i)) continue;
        const Kernel ker = disc.kernel_at(i);
        const auto nbr = disc.neighbours.of(i);
        const Real xi = cloud.positions[static_cast<std::size_t>(i)][0];
        K.resize(nbr.size());
        DK.resize(nbr.size());
        for (std::size_t k = 0; k < nbr.size(); ++k) {
          const Real d = cloud.positions[static_cast<std::size_t>(nbr[k])][0] - xi;
          K[k] = ker.W(std::abs(d));
          DK[k] = ker.dW_over_r(std::abs(d)) * d;  // DW_i(x_j) = d/dx W(x - x_i) at x_j
        }
        Real cond = 1;
        if (corrected_) {
          // (42): sum_j v_j W_ij d_j^m (a s^3 + b s + c) = delta_m0, m = 0, 1, 3 (self included).
          const Real H = ker.support();
          C.setZero(3, 3);
          for (std::size_t k = 0; k <= nbr.size(); ++k) {
            const Index j = k < nbr.size() ? nbr[k] : i;
            const Real d = cloud.positions[static_cast<std::size_t>(j)][0] - xi, sj = d / H;
            const Real w = v[static_cast<std::size_t>(j)] * (k < nbr.size() ? K[k] : ker.W(0));
            const Real moment[3] = {1, d, d * d * d}, basis[3] = {sj * sj * sj, sj, 1};
            for (int r = 0; r < 3; ++r)
              for (int q = 0; q < 3; ++q) C(r, q) += w * moment[r] * basis[q];
          }
          cond = taylor::equilibrated_inverse(C, Cinv);
          if (std::isfinite(cond)) {
            const Real a = Cinv(0, 0), b = Cinv(1, 0), c = Cinv(2, 0);
            for (std::size_t k = 0; k < nbr.size(); ++k) {
              const Real sj = (cloud.positions[static_cast<std::size_t>(nbr[k])][0] - xi) / H;
              const Real Cj = a * sj * sj * sj + b * sj + c, dCj = (3 * a * sj * sj + b) / H;
              DK[k] = dCj * K[k] + Cj * DK[k];
              K[k] = Cj * K[k];
            }
          }
        }
        if (std::isfinite(cond)) {
          // (35)-(36): [A11 A12; A21 A22] (DB, D2B) = sum_j v_j B_ji (K, DK).
          A.setZero(2, 2);
          for (std::size_t k = 0; k < nbr.size(); ++k) {
            const Real d = cloud.positions[static_cast<std::size_t>(nbr[k])][0] - xi;
            const Real vj = v[static_cast<std::size_t>(nbr[k])];
            A(0, 0) += vj * d * K[k];
            A(0, 1) += 0.5 * vj * d * d * K[k];
            A(1, 0) += vj * d * DK[k];
            A(1, 1) += 0.5 * vj * d * d * DK[k];
          }
          cond = std::max(cond, taylor::equilibrated_inverse(A, Ainv));
        }
        s.condition[static_cast<std::size_t>(i)] = cond;
        if (!std::isfinite(cond)) continue;
        const Real grad_a =
            req.kind != OperatorKind::DivAGrad
                ? 0.0
                : taylor::coefficient_gradient(req, i, nbr, 1, [&](std::size_t k) {
                    return Vec3(v[static_cast<std::size_t>(nbr[k])] * (Ainv(0, 0) * K[k] + Ainv(0, 1) * DK[k]), 0, 0);
                  })[0];
        for (std::size_t k = 0; k < nbr.size(); ++k) {
          const Real vj = v[static_cast<std::size_t>(nbr[k])];
          const Real wd = vj * (Ainv(0, 0) * K[k] + Ainv(0, 1) * DK[k]);
          const Real wdd = vj * (Ainv(1, 0) * K[k] + Ainv(1, 1) * DK[k]);
          Real w = wd;
          if (second) w = req.kind == OperatorKind::Laplacian ? wdd : (*req.coefficient)[i] * wdd + grad_a * wd;
          s.values[0][static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)))] = w;
        }
      }
    }
    set_difference_diagonal(s);
    taylor::enforce_condition(s, policy_, cloud);
    return s;
  }

 private:
  MethodInfo info_;
  bool corrected_;
  std::string volume_;
  taylor::SingularPolicy policy_;
};

}  // namespace

MethodInfo mfpm_info() {
  return taylor::with_coefficient_gradient({"mfpm",
          "[AAR] (33)-(37)",
          "modified FPM (1D): 2x2 Taylor projection on W and DW giving first and second derivative together",
          "second derivative O(h^2) inside, O(h) at the boundary (derivative test order 1; rod order 2)",
          operators,
          taylor::corrected_method_options()});
}
MethodInfo fpm2o_info() {
  return taylor::with_coefficient_gradient({"fpm2o",
          "[AAR] (39)-(44)",
          "second-order FPM (1D): modified FPM with the kernel corrected by (a s^3 + b s + c) near the boundary",
          "O(h^2) everywhere, boundary included (derivative and rod tests order 2, also on perturbed particles)",
          operators,
          taylor::corrected_method_options()});
}

std::unique_ptr<Method> make_mfpm(const MethodOptions& o) { return std::make_unique<ModifiedFpm>(mfpm_info(), false, o); }
std::unique_ptr<Method> make_fpm2o(const MethodOptions& o) { return std::make_unique<ModifiedFpm>(fpm2o_info(), true, o); }

}  // namespace vrsph
