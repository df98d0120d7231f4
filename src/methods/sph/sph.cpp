// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/pair_mean.hpp>
#include <vrsph/methods/sph/sph.hpp>

namespace vrsph {

MethodInfo sph_info() {
  MethodInfo info{"sph",
          "[QW] §2.1",
          "traditional SPH: kernel-gradient gradient, Brookshaw Laplacian, Morris div(a grad)",
          "O(h^2) smoothing + O((dx/h)^{p+2}) discretisation error on lattices; gradient non-convergent and "
          "Laplacian divergent on perturbed particles; 1st order Poisson with boundary truncation",
          {OperatorKind::Value, OperatorKind::Dx, OperatorKind::Dy, OperatorKind::Dz, OperatorKind::Gradient,
           OperatorKind::Laplacian, OperatorKind::DivAGrad},
          {{"volume", "dx (v_j = dx^d) | shepard (v_j = 1/sum_k W_jk); default dx"}, pair_mean_option()}};
  info.monotone = true;
  return info;
}

std::vector<Real> sph_volumes(const Discretisation& disc, SphVolume mode) {
  const Index n = disc.cloud.size();
  if (mode == SphVolume::Spacing) {
    check<InputError>(disc.spacing > 0, "particle volumes v = dx^d (SPH, gpm lattice) need a positive particle spacing, got ", disc.spacing);
    return std::vector<Real>(static_cast<std::size_t>(n), std::pow(disc.spacing, disc.cloud.dim));
  }
  return shepard_volumes(
      disc, [&disc](Index j) { return [k = disc.kernel_at(j)](Real r) { return k.W(r); }; }, "SPH volumes");
}

namespace {

class Sph final : public Method {
 public:
  explicit Sph(const MethodOptions& o)
      : info_(sph_info()),
        volume_(o.get_choice("volume", "dx", {"dx", "shepard"}) == "dx" ? SphVolume::Spacing : SphVolume::Shepard),
        mean_(read_pair_mean(o)) {}
  const MethodInfo& info() const override { return info_; }
  int reach() const override { return volume_ == SphVolume::Shepard ? 2 : 1; }
  // Rows read distances, pair vectors (Discretisation::neighbour_position), the neighbours'
  // coefficient values and volumes; Shepard volumes sum each neighbour's own distances. A
  // minimum-image list then gives every row (Operators on a periodic box: the Verlet skin).
  bool reads_periodic_pairs(const StencilRequest& /*req*/) const override { return true; }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req, reads_periodic_pairs(req));
    check<InputError>(disc.neighbours.distances.size() == disc.neighbours.indices.size(),
                      "SPH needs neighbour lists with cached distances");
    const auto v = sph_volumes(disc, volume_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, disc.cloud.dim, info_.name);
    const auto& cloud = disc.cloud;
    const int axis = req.kind == OperatorKind::Dy ? 1 : req.kind == OperatorKind::Dz ? 2 : 0;
#pragma omp parallel for schedule(dynamic, 256)
    for (Index i = 0; i < cloud.size(); ++i) {
      if (req.rows.empty() ? cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost : !req.rows[static_cast<std::size_t>(i)]) continue;
      const Kernel ker = disc.kernel_at(i);
      const auto nbr = disc.neighbours.of(i);
      const auto dist = disc.neighbours.distances_of(i);
      const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
      for (std::size_t k = 0; k < nbr.size(); ++k) {
        const auto j = static_cast<std::size_t>(nbr[k]);
        const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)));
        const Real r = dist[k];
        switch (req.kind) {
          case OperatorKind::Value:
            s.values[0][slot] = v[j] * ker.W(r);
            break;
          case OperatorKind::Dx:
          case OperatorKind::Dy:
          case OperatorKind::Dz:
          case OperatorKind::Gradient: {
            // grad_i W_ij = W'(r) (x_i - x_j)/r
            const Vec3 g = v[j] * ker.dW_over_r(r) * (xi - disc.neighbour_position(i, static_cast<Index>(k)));
            if (req.kind == OperatorKind::Gradient)
              for (int c = 0; c < cloud.dim; ++c) s.values[static_cast<std::size_t>(c)][slot] = g[c];
            else
              s.values[0][slot] = g[axis];
            break;
          }
          case OperatorKind::Laplacian:
            s.values[0][slot] = -2 * v[j] * ker.dW_over_r(r);
            break;
          case OperatorKind::DivAGrad: {
            const Field& a = *req.coefficient;
            s.values[0][slot] = -v[j] * pair_sum(mean_, a[i], a[static_cast<Eigen::Index>(j)]) * ker.dW_over_r(r);
            break;
          }
          case OperatorKind::Hessian: break;  // hessian_rows builds it for every method (check_request refuses it here)
        }
      }
      if (req.kind == OperatorKind::Value)
        s.values[0][static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])] = v[static_cast<std::size_t>(i)] * ker.W(0);
    }
    if (req.kind != OperatorKind::Value) set_difference_diagonal(s);
    return s;
  }

 private:
  MethodInfo info_;
  SphVolume volume_;
  PairMean mean_;
};

}  // namespace

std::unique_ptr<Method> make_sph(const MethodOptions& options) { return std::make_unique<Sph>(options); }

}  // namespace vrsph
