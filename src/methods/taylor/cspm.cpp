// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/taylor/cspm.hpp>
#include <vrsph/methods/taylor/local_system.hpp>

namespace vrsph {

namespace {

using taylor::SmallMatrix;

enum class SecondDerivative { KernelHessian /*cspm*/, KernelOnly /*chen-beraun, [AAR](20)*/ };

class Corrective final : public Method {
 public:
  Corrective(MethodInfo info, SecondDerivative second, const MethodOptions& o)
      : info_(std::move(info)), second_(second), volume_(o.get_choice("volume", "dx", {"dx", "shepard"})),
        policy_(taylor::read_singular_policy(o)) {}
  const MethodInfo& info() const override { return info_; }
  // Shepard volumes sum each neighbour's own list: one more ring of particles than the rows
  // (a rank's halo, a periodic box's images; with one ring the halo's last volumes were short).
  int reach() const override { return info().stencil_rings + (volume_ == "shepard" ? 1 : 0); }
  // Rows read pair vectors (Discretisation::neighbour_position), the neighbours' volumes (Shepard:
  // sums over each neighbour's own distances) and coefficient values: a minimum-image list gives
  // every row (Operators on a periodic box: the Verlet skin).
  bool reads_periodic_pairs(const StencilRequest& /*req*/) const override { return true; }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req, reads_periodic_pairs(req));
    const auto& cloud = disc.cloud;
    const int dim = cloud.dim;
    const auto v = taylor::method_volumes(disc, volume_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, dim, info_.name);
    s.condition.assign(static_cast<std::size_t>(cloud.size()), 0);
    const bool second = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;

#pragma omp parallel
    {
      std::vector<Vec3> g;  // corrected gradient weights of the row
      std::vector<Vec3> d;  // the row's pair vectors x_j - x_i (periodic: to the image it sees), formed once
      SmallMatrix A(dim, dim), Ainv(dim, dim);
#pragma omp for schedule(dynamic, 128)
      for (Index i = 0; i < cloud.size(); ++i) {
        if (!taylor::wants_row(cloud, req, i)) continue;
        const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
        d.resize(disc.neighbours.of(i).size());
        for (std::size_t k = 0; k < d.size(); ++k) d[k] = disc.neighbour_position(i, static_cast<Index>(k)) - xi;
        if (req.kind == OperatorKind::Value) {
          shepard_row(disc, v, i, d, s);
          continue;
        }
        const Real cond = corrected_gradient(disc, v, i, d, A, Ainv, g);
        if (!std::isfinite(cond)) {
          s.condition[static_cast<std::size_t>(i)] = cond;
        } else if (!second) {
          s.condition[static_cast<std::size_t>(i)] = cond;
          store_gradient_row(req, dim, i, g, s);
        } else {
          second_derivative_row(disc, req, v, i, d, g, cond, s);
        }
      }
    }
    if (req.kind != OperatorKind::Value) set_difference_diagonal(s);
    taylor::enforce_condition(s, policy_, cloud);
    return s;
  }

 private:
  // Value rows: the Shepard-normalised kernel sum.
  static void shepard_row(const Discretisation& disc, const std::vector<Real>& v, Index i, const std::vector<Vec3>& d,
                          Stencil& s) {
    const Kernel ker = disc.kernel_at(i);
    const auto nbr = disc.neighbours.of(i);
    Real sum = v[static_cast<std::size_t>(i)] * ker.W(0);
    for (std::size_t k = 0; k < nbr.size(); ++k) sum += v[static_cast<std::size_t>(nbr[k])] * ker.W(d[k].norm());
    const bool ok = sum > 0 && std::isfinite(sum);
    s.condition[static_cast<std::size_t>(i)] = ok ? 1 : std::numeric_limits<Real>::infinity();
    if (!ok) return;
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const auto j = static_cast<std::size_t>(nbr[k]);
      s.values[0][static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)))] =
          v[j] * ker.W(d[k].norm()) / sum;
    }
    s.values[0][static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])] = v[static_cast<std::size_t>(i)] * ker.W(0) / sum;
  }

  // The corrected gradient weights g_k = v_k A_i^{-T} grad W of row i, with the correction
  // matrix A_i = sum_j v_j x_ji ⊗ grad_i W_ij. Returns A_i's condition (infinite: singular,
  // g untouched).
  static Real corrected_gradient(const Discretisation& disc, const std::vector<Real>& v, Index i,
                                 const std::vector<Vec3>& d, SmallMatrix& A, SmallMatrix& Ainv, std::vector<Vec3>& g) {
    const int dim = disc.cloud.dim;
    const Kernel ker = disc.kernel_at(i);
    const auto nbr = disc.neighbours.of(i);
    A.setZero(dim, dim);
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3& xji = d[k];
      const Vec3 gw = -ker.dW_over_r(xji.norm()) * xji;  // grad_i W_ij = W'(r) x_ij / r
      for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b) A(a, b) += v[static_cast<std::size_t>(nbr[k])] * xji[a] * gw[b];
    }
    const Real cond = taylor::equilibrated_inverse(A, Ainv);
    if (!std::isfinite(cond)) return cond;
    g.assign(nbr.size(), Vec3::Zero());
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3& xji = d[k];
      const Vec3 gw = -ker.dW_over_r(xji.norm()) * xji;
      for (int a = 0; a < dim; ++a) {
        Real acc = 0;
        for (int b = 0; b < dim; ++b) acc += Ainv(b, a) * gw[b];  // A^{-T} grad W
        g[k][a] = v[static_cast<std::size_t>(nbr[k])] * acc;
      }
    }
    return cond;
  }

  static void store_gradient_row(const StencilRequest& req, int dim, Index i, const std::vector<Vec3>& g, Stencil& s) {
    const int axis = req.kind == OperatorKind::Dy ? 1 : req.kind == OperatorKind::Dz ? 2 : 0;
    for (std::size_t k = 0; k < g.size(); ++k) {
      const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)));
      if (req.kind == OperatorKind::Gradient)
        for (int c = 0; c < dim; ++c) s.values[static_cast<std::size_t>(c)][slot] = g[k][c];
      else
        s.values[0][slot] = g[k][axis];
    }
  }

  // Second derivative: per direction (cspm) or isotropic (chen-beraun); cond is A_i's.
  void second_derivative_row(const Discretisation& disc, const StencilRequest& req, const std::vector<Real>& v, Index i,
                             const std::vector<Vec3>& d, const std::vector<Vec3>& g, Real cond, Stencil& s) const {
    const int dim = disc.cloud.dim;
    const Kernel ker = disc.kernel_at(i);
    const auto nbr = disc.neighbours.of(i);
    const int directions = second_ == SecondDerivative::KernelHessian ? dim : 1;
    Vec3 D = Vec3::Zero(), Dabs = Vec3::Zero();
    std::array<Vec3, 3> S{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3& xji = d[k];
      const Real r = xji.norm();
      const Real vj = v[static_cast<std::size_t>(nbr[k])];
      for (int a = 0; a < directions; ++a) {
        const Real q = weight_function(ker, xji, r, a);
        const Real moment = second_ == SecondDerivative::KernelHessian ? xji[a] * xji[a] : xji.squaredNorm();
        D[a] += 0.5 * vj * moment * q;
        Dabs[a] += 0.5 * vj * moment * std::abs(q);
        S[static_cast<std::size_t>(a)] += vj * q * xji;
      }
    }
    for (int a = 0; a < directions; ++a) {
      const Real c = std::abs(D[a]) > 0 ? Dabs[a] / std::abs(D[a]) : std::numeric_limits<Real>::infinity();
      cond = std::max(cond, c);
    }
    s.condition[static_cast<std::size_t>(i)] = cond;
    if (!std::isfinite(cond)) return;
    const Vec3 grad_a = req.kind != OperatorKind::DivAGrad
                            ? Vec3::Zero()
                            : taylor::coefficient_gradient(req, i, nbr, dim, [&](std::size_t k) { return g[k]; });
    const Real iso = second_ == SecondDerivative::KernelOnly ? static_cast<Real>(dim) : 1;
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3& xji = d[k];
      const Real r = xji.norm();
      Real w = 0;
      for (int a = 0; a < directions; ++a)
        w += iso * (v[static_cast<std::size_t>(nbr[k])] * weight_function(ker, xji, r, a) -
                    S[static_cast<std::size_t>(a)].dot(g[k])) / D[a];
      if (req.kind == OperatorKind::DivAGrad) w = (*req.coefficient)[i] * w + grad_a.dot(g[k]);
      s.values[0][static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)))] = w;
    }
  }

  // cspm: d2W/dx_a^2 at x_ij; chen-beraun: W itself.
  Real weight_function(const Kernel& ker, const Vec3& xji, Real r, int a) const {
    if (second_ == SecondDerivative::KernelOnly) return ker.W(r);
    std::array<int, 3> alpha{0, 0, 0};
    alpha[static_cast<std::size_t>(a)] = 2;
    return taylor::kernel_derivative(ker, -xji, r, alpha);
  }

  MethodInfo info_;
  SecondDerivative second_;
  std::string volume_;
  taylor::SingularPolicy policy_;
};

}  // namespace

MethodInfo cspm_info() {
  return taylor::with_coefficient_gradient({"cspm",
          "[QW] §2.2 (\"CSPH\"); [CBC]",
          "corrective SPH: full-matrix corrected kernel gradient, Laplacian from second kernel derivatives "
          "(diagonal Hessian approximation)",
          "gradient exact for linear fields, O(h) on perturbed particles; Laplacian below first order on perturbed "
          "particles ([QW] Fig. 4)",
          taylor::every_operator(),
          taylor::corrected_method_options()});
}

MethodInfo chen_beraun_info() {
  return taylor::with_coefficient_gradient({"chen-beraun",
          "[AAR] (16), (20); [CB]",
          "Chen–Beraun corrective SPH: corrected first derivative (16), kernel-only second derivative (20) "
          "(isotropic extension in 2D/3D)",
          "O(h^2) inside; first derivative O(h), second derivative O(1) at the boundary (no max-norm convergence in "
          "the derivative test, first order for the rod, [AAR] §5)",
          taylor::every_operator(),
          taylor::corrected_method_options()});
}

std::unique_ptr<Method> make_cspm(const MethodOptions& o) {
  return std::make_unique<Corrective>(cspm_info(), SecondDerivative::KernelHessian, o);
}
std::unique_ptr<Method> make_chen_beraun(const MethodOptions& o) {
  return std::make_unique<Corrective>(chen_beraun_info(), SecondDerivative::KernelOnly, o);
}

}  // namespace vrsph
