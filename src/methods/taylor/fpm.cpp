// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/gradient_consistency.hpp>
#include <vrsph/methods/taylor/fpm.hpp>
#include <vrsph/methods/taylor/local_system.hpp>

namespace vrsph {

namespace {

using taylor::SmallMatrix;
using taylor::SmallVector;

std::vector<std::pair<std::string, std::string>> common_options(bool with_variant) {
  auto o = taylor::corrected_method_options();
  o.emplace_back("gradient_order",
                 "3 (default: the quadratic fit's gradient rows raised to exactness on cubics by their smallest "
                 "kernel-weighted change: O(h^3) inside; a row whose cubic fit is singular or worse conditioned than 1e4 "
                 "keeps the quadratic one) | "
                 "2 (from the quadratic fit: exact for quadratics, second-order one-sided gradients) | 1 (from the "
                 "linear fit, [QW](2.15) as published: O(h) on perturbed particles; what the reproductions pin)");
  if (with_variant)
    o.emplace_back("variant", "liu (default: Hessian of W as test functions) | qw ([QW](2.18), 1D only: Y_ij instead of W'')");
  return o;
}

enum class TestFunctions { KernelDerivatives, KernelDerivativesQw, KernelTimesMonomials };

class TaylorProjection final : public Method {
 public:
  TaylorProjection(MethodInfo info, TestFunctions tests, const MethodOptions& o) : info_(std::move(info)), tests_(tests) {
    volume_ = o.get_choice("volume", "dx", {"dx", "shepard"});
    const std::string order = o.get_choice("gradient_order", "3", {"1", "2", "3"});
    quadratic_gradient_ = order != "1";
    cubic_gradient_ = order == "3";
    if (tests_ != TestFunctions::KernelTimesMonomials &&
        o.get_choice("variant", "liu", {"liu", "qw"}) == "qw")
      tests_ = TestFunctions::KernelDerivativesQw;
    policy_ = taylor::read_singular_policy(o);
  }
  const MethodInfo& info() const override { return info_; }
  // Shepard volumes sum each neighbour's own list: one more ring of particles than the rows
  // (a rank's halo, a periodic box's images; with one ring the halo's last volumes were short).
  int reach() const override { return info().stencil_rings + (volume_ == "shepard" ? 1 : 0); }

  // Rows read pair vectors, the neighbours' values and volumes (Shepard: sums over each
  // neighbour's own distances, as SPH's); a coefficient's gradient is left to the images.
  bool reads_periodic_pairs(const StencilRequest& req) const override { return req.kind != OperatorKind::DivAGrad; }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req, reads_periodic_pairs(req));
    const auto& cloud = disc.cloud;
    const int dim = cloud.dim;
    check<ConfigError>(tests_ != TestFunctions::KernelDerivativesQw || dim == 1,
                       "fpm variant=qw ([QW](2.18)) is defined in 1D only");
    const bool second = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad || quadratic_gradient_;
    const auto basis = taylor::multi_indices(dim, second ? 2 : 1, true);
    const auto m = static_cast<Eigen::Index>(basis.size());
    std::vector<int> grad_pos(static_cast<std::size_t>(dim)), hess_pos(static_cast<std::size_t>(dim));
    for (int k = 0; k < dim; ++k) {
      std::array<int, 3> e{0, 0, 0};
      e[static_cast<std::size_t>(k)] = 1;
      grad_pos[static_cast<std::size_t>(k)] = taylor::position_of(basis, e);
      if (second) {
        e[static_cast<std::size_t>(k)] = 2;
        hess_pos[static_cast<std::size_t>(k)] = taylor::position_of(basis, e);
      }
    }
    const auto v = taylor::method_volumes(disc, volume_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, dim, info_.name);
    s.condition.assign(static_cast<std::size_t>(cloud.size()), 0);

#pragma omp parallel
    {
      std::vector<Real> psi;  // test functions of every neighbour, m per neighbour (self last)
      SmallMatrix M(m, m), Minv(m, m);
      OutputRows rows{};
#pragma omp for schedule(dynamic, 128)
      for (Index i = 0; i < cloud.size(); ++i) {
        if (!taylor::wants_row(cloud, req, i)) continue;
        const Kernel ker = disc.kernel_at(i);
        const auto nbr = disc.neighbours.of(i);
        const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
        const std::size_t count = nbr.size() + 1;
        psi.resize(count * static_cast<std::size_t>(m));
        M.setZero(m, m);
        for (std::size_t k = 0; k < count; ++k) {
          const Index j = k < nbr.size() ? nbr[k] : i;
          // The pair vector (a periodic image's when the list crosses periodic faces).
          const Vec3 xji = k < nbr.size() ? Vec3(disc.neighbour_position(i, static_cast<Index>(k)) - xi) : Vec3::Zero();
          const Real r = xji.norm();
          Real* ps = psi.data() + k * static_cast<std::size_t>(m);
          const taylor::PairKernel kv =
              taylor::pair_kernel(ker, r, tests_ == TestFunctions::KernelTimesMonomials ? 0 : second ? 2 : 1);
          for (Eigen::Index a = 0; a < m; ++a) ps[a] = test_function(kv, xji, r, basis[static_cast<std::size_t>(a)]);
          const Real vj = v[static_cast<std::size_t>(j)];
          for (Eigen::Index b = 0; b < m; ++b) {
            const Real pb = vj * taylor::monomial(xji, basis[static_cast<std::size_t>(b)], true);
            if (pb == 0) continue;
            for (Eigen::Index a = 0; a < m; ++a) M(a, b) += ps[a] * pb;
          }
        }
        const Real cond = taylor::equilibrated_inverse(M, Minv);
        s.condition[static_cast<std::size_t>(i)] = cond;
        if (!std::isfinite(cond)) continue;
        // (grad a)_i for div(a grad u): analytic or from the same fit.
        const Vec3 grad_a =
            req.kind != OperatorKind::DivAGrad
                ? Vec3::Zero()
                : taylor::coefficient_gradient(req, i, nbr, dim, [&](std::size_t k) {
                    const SmallVector w = Minv * Eigen::Map<const SmallVector>(psi.data() + k * static_cast<std::size_t>(m), m);
                    Vec3 g = Vec3::Zero();
                    for (int c = 0; c < dim; ++c) g[c] = v[static_cast<std::size_t>(nbr[k])] * w[grad_pos[static_cast<std::size_t>(c)]];
                    return g;
                  });
        // Only the rows of M^-1 the stencil stores, combined as it stores them (a Laplacian
        // weight is the sum of the d second-derivative rows): per neighbour one dot product of
        // length m per output instead of the whole product M^-1 psi_k (m outputs, most unread).
        const int outputs = stored_rows(req, i, Minv, grad_pos, hess_pos, grad_a, rows);
        for (std::size_t k = 0; k < count; ++k) {
          const Index j = k < nbr.size() ? nbr[k] : i;
          const bool self = k == nbr.size();
          if (self && req.kind != OperatorKind::Value) continue;  // difference form: diagonal set below
          const auto slot = static_cast<std::size_t>(self ? s.diag[static_cast<std::size_t>(i)]
                                                          : neighbour_slot(s, i, static_cast<Index>(k)));
          const Real* ps = psi.data() + k * static_cast<std::size_t>(m);
          const Real vj = v[static_cast<std::size_t>(j)];
          for (int c = 0; c < outputs; ++c) {
            const auto& row = rows[static_cast<std::size_t>(c)];
            Real w = 0;
            for (Eigen::Index b = 0; b < m; ++b) w += row[static_cast<std::size_t>(b)] * ps[b];
            s.values[static_cast<std::size_t>(c)][slot] = vj * w;
          }
        }
      }
    }
    if (req.kind != OperatorKind::Value) set_difference_diagonal(s);
    taylor::enforce_condition(s, policy_, cloud);
    if (cubic_gradient_ && traits(req.kind).derivative_order == 1) raise_to_cubic_exactness(disc, req, s);
    return s;
  }

 private:
  using OutputRows = std::array<std::array<Real, taylor::max_unknowns>, 3>;

  // The combinations of M^-1's rows that row i stores, one per output array: the value, a
  // derivative, the gradient's components, the Laplacian (trace of the Hessian) or
  // a Δu + ∇a·∇u. Returns their number.
  static int stored_rows(const StencilRequest& req, Index i, const SmallMatrix& Minv, const std::vector<int>& grad_pos,
                         const std::vector<int>& hess_pos, const Vec3& grad_a, OutputRows& rows) {
    const int dim = static_cast<int>(grad_pos.size());
    const auto m = static_cast<std::size_t>(Minv.cols());
    const auto copy_row = [&](std::size_t out, int r) {
      for (std::size_t b = 0; b < m; ++b) rows[out][b] = Minv(r, static_cast<Eigen::Index>(b));
    };
    switch (req.kind) {
      case OperatorKind::Value: copy_row(0, 0); return 1;
      case OperatorKind::Dx:
      case OperatorKind::Dy:
      case OperatorKind::Dz: {
        const int axis = req.kind == OperatorKind::Dy ? 1 : req.kind == OperatorKind::Dz ? 2 : 0;
        copy_row(0, grad_pos[static_cast<std::size_t>(axis)]);
        return 1;
      }
      case OperatorKind::Gradient:
        for (int c = 0; c < dim; ++c) copy_row(static_cast<std::size_t>(c), grad_pos[static_cast<std::size_t>(c)]);
        return dim;
      case OperatorKind::Laplacian:
      case OperatorKind::DivAGrad: {
        const Real a = req.kind == OperatorKind::Laplacian ? 1 : (*req.coefficient)[i];
        for (std::size_t b = 0; b < m; ++b) {
          const auto bb = static_cast<Eigen::Index>(b);
          Real lap = 0, adv = 0;
          for (int c = 0; c < dim; ++c) {
            lap += Minv(hess_pos[static_cast<std::size_t>(c)], bb);
            adv += grad_a[c] * Minv(grad_pos[static_cast<std::size_t>(c)], bb);
          }
          rows[0][b] = req.kind == OperatorKind::Laplacian ? lap : a * lap + adv;
        }
        return 1;
      }
      case OperatorKind::Hessian: break;  // hessian_rows builds it for every method (check_request refuses it here)
    }
    return 0;
  }
  // The test function of multi-index alpha at one pair, from the pair's kernel values.
  Real test_function(const taylor::PairKernel& kv, const Vec3& xji, Real r, const std::array<int, 3>& alpha) const {
    const Vec3 xij = -xji;
    switch (tests_) {
      case TestFunctions::KernelDerivatives: return taylor::kernel_derivative(kv, xij, r, alpha);
      case TestFunctions::KernelDerivativesQw:
        // [QW](2.18): Y_ij = -2 W'(r)/r replaces W'' in the third (degree-2) test function.
        return alpha[0] == 2 ? -2 * kv.dW_over_r : taylor::kernel_derivative(kv, xij, r, alpha);
      case TestFunctions::KernelTimesMonomials: return kv.W * taylor::monomial(xji, alpha, false);
    }
    return 0;
  }

  MethodInfo info_;
  TestFunctions tests_;
  std::string volume_;
  bool quadratic_gradient_ = false;  ///< value/gradient from the second-order (quadratic) fit
  bool cubic_gradient_ = false;      ///< gradient_order=3: those rows raised to cubic exactness
  taylor::SingularPolicy policy_;
};

}  // namespace

MethodInfo fpm_info() {
  return taylor::with_coefficient_gradient({"fpm",
          "[QW] (2.13)-(2.19); [AAR] (27)-(30); [LL]",
          "finite particle method: Taylor expansion projected on W and its derivatives (per-particle 1+d or "
          "(d+1)(d+2)/2 system)",
          "gradient exact for cubics (default gradient_order=3: O(h^3) inside; gradient_order=1 as published: exact for "
          "linears, O(h) on irregular particles, [QW] Figs. 3, 6; [AAR]: O(h^2) inside, O(h) at the boundary); Laplacian "
          "exact for quadratics, O(h) on irregular particles ([QW] Fig. 4)",
          taylor::every_operator(),
          common_options(true)});
}

MethodInfo kgf_info() {
  return taylor::with_coefficient_gradient({"kgf",
          "[QW] §2.2; [HLLP]",
          "kernel-gradient-free SPH: FPM with test functions W_ij (x_j - x_i)^alpha (weighted least squares)",
          "gradient exact for cubics (default gradient_order=3; gradient_order=1 as published: O(h) on perturbed particles, "
          "[QW] Fig. 3); Laplacian exact for quadratics, O(h) on perturbed particles ([QW] Fig. 4)",
          taylor::every_operator(),
          common_options(false)});
}

std::unique_ptr<Method> make_fpm(const MethodOptions& o) {
  return std::make_unique<TaylorProjection>(fpm_info(), TestFunctions::KernelDerivatives, o);
}
std::unique_ptr<Method> make_kgf(const MethodOptions& o) {
  return std::make_unique<TaylorProjection>(kgf_info(), TestFunctions::KernelTimesMonomials, o);
}

}  // namespace vrsph
