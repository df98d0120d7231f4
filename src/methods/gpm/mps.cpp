// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include <vrsph/methods/gpm/mps.hpp>
#include <vrsph/methods/particle_volumes.hpp>
#include <vrsph/methods/sph/sph.hpp>

namespace vrsph {

MethodInfo mps_info() {
  return {"mps",
          "[IM] (61)-(62), Appendix A",
          "moving particle semi-implicit: gradient and Laplacian with the MPS weight, number density n and lambda",
          "O(h^min(2, m-2)) Laplacian for a particle set regular of order m; O(h^min(2, m-1)) gradient if the weight "
          "satisfies Hypothesis 2 with k = 0 ([IM] Corollary 2; the classic weight is outside the class W)",
          {OperatorKind::Dx, OperatorKind::Dy, OperatorKind::Dz, OperatorKind::Gradient, OperatorKind::Laplacian},
          {{"weight", "classic (1/r - 1, normalised; 2D/3D, default) | pi1 | pi2 | pi3 ([IM] reference weights)"},
           {"volume", "lattice (1/n = dx^d, default) | uniform (1/n = |Omega|/N, [IM] Corollary 2)"}}};
}

namespace {

// The weight w(s) on [0, 1) normalised over R^d, and its second moment ∫|y|^2 w(|y|) dy.
struct MpsWeight {
  std::function<Real(Real)> w;
  Real second_moment = 0;
};

MpsWeight mps_weight(const std::string& name, int d) {
  const Real sphere = d == 1 ? 2 : d == 2 ? 2 * std::numbers::pi : 4 * std::numbers::pi;  // |S^(d-1)|
  if (name == "classic") {
    check<ConfigError>(d >= 2, "mps weight=classic (1/r - 1) is not integrable in 1D; use weight=pi1|pi2|pi3");
    // ∫ r^(d-1) (1/r - 1) dr over [0,1) = 1/(d-1) - 1/d; second moment ∫ r^(d+1) (1/r - 1) = 1/(d+1) - 1/(d+2).
    const Real norm = sphere * (1.0 / (d - 1) - 1.0 / d);
    return {[norm](Real s) { return s < 1 ? (1 / s - 1) / norm : 0.0; }, sphere * (1.0 / (d + 1) - 1.0 / (d + 2)) / norm};
  }
  const ReferenceWeight rw = reference_weight(name, d);
  return {[rw](Real s) { return rw.value(s); }, sphere * rw.radial_moment(2)};
}

class Mps final : public Method {
 public:
  explicit Mps(const MethodOptions& o)
      : info_(mps_info()),
        weight_(o.get_choice("weight", "classic", {"classic", "pi1", "pi2", "pi3"})),
        uniform_(o.get_choice("volume", "lattice", {"lattice", "uniform"}) == "uniform") {}
  const MethodInfo& info() const override { return info_; }
  // Rows read distances and pair vectors only (the volumes are one number): a minimum-image
  // list gives every row.
  bool reads_periodic_pairs(const StencilRequest& /*req*/) const override { return true; }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req, reads_periodic_pairs(req));
    const auto& cloud = disc.cloud;
    const int d = cloud.dim;
    const MpsWeight mw = mps_weight(weight_, d);
    const std::vector<Real> V = uniform_ ? particle_volumes(disc, ParticleVolumes::Uniform) : sph_volumes(disc, SphVolume::Spacing);
    const Real inv_n = V.empty() ? 0 : V[0];  // one number density for all particles
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, d, info_.name);
#pragma omp parallel for schedule(dynamic, 256)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (!row_requested(cloud, req, i)) continue;
      const Real h = disc.neighbours.radius(i);
      const Real hd = std::pow(h, d);
      const Real lambda = h * h * mw.second_moment;
      const auto nbr = disc.neighbours.of(i);
      const auto dist = disc.neighbours.distances_of(i);
      for (std::size_t k = 0; k < nbr.size(); ++k) {
        const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)));
        const Real r = dist[k];
        const Real wh = mw.w(r / h) / hd;
        if (req.kind == OperatorKind::Laplacian) {
          s.values[0][slot] = 2 * d * inv_n * wh / lambda;
        } else {
          const Vec3 g = (d * inv_n * wh / (r * r)) * (disc.neighbour_position(i, static_cast<Index>(k)) - cloud.positions[si]);
          store_pair_gradient(s, req.kind, d, slot, g);
        }
      }
    }
    set_difference_diagonal(s);
    return s;
  }

 private:
  MethodInfo info_;
  std::string weight_;
  bool uniform_;
};

}  // namespace

std::unique_ptr<Method> make_mps(const MethodOptions& options) { return std::make_unique<Mps>(options); }

}  // namespace vrsph
