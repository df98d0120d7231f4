// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include <vrsph/methods/gpm/gpm.hpp>
#include <vrsph/methods/gpm/gpm_pairs.hpp>
#include <vrsph/methods/pair_mean.hpp>
#include <vrsph/methods/particle_volumes.hpp>
#include <vrsph/methods/sph/sph.hpp>

namespace vrsph {

MethodInfo gpm_info() {
  MethodInfo info{"gpm",
                  "[IM] (2)-(4)",
                  "generalized particle method: interpolant, gradient and Laplacian from the [IM] reference weights",
                  "O(h^min(m-1, n+1)) interpolant and gradient, O(h^min(m-2, n+1)) Laplacian for a particle set regular "
                  "of order m and a weight with Hypothesis 1 of order n ([IM] Thm 3)",
                  {OperatorKind::Value, OperatorKind::Dx, OperatorKind::Dy, OperatorKind::Dz, OperatorKind::Gradient,
                   OperatorKind::Laplacian, OperatorKind::DivAGrad},
                  {{"weight", "1 | 2 | 3: the weights pi<k>, grad<k>, delta<k> of [IM] §2.6 (default 2: SPH with the cubic "
                              "spline)"},
                   {"volume", "lattice (V_j = dx^d, default) | shepard (V_j = 1 / sum_k pi<k>_h(r_jk), self included) | "
                              "uniform (|Omega|/N, [IM] 5.4) | voronoi (clipped Voronoi cell measures, d_N = 0) | vrsph "
                              "(VRSPH's Laplace volumes averaged per particle)"},
                   pair_mean_option()}};
  return info;
}

std::vector<Real> gpm_volumes(const Discretisation& disc, const std::string& volume, const std::string& family) {
  if (volume == "lattice") return sph_volumes(disc, SphVolume::Spacing);  // V_j = dx^d, as SPH's
  if (volume != "shepard") return particle_volumes(disc, parse_particle_volumes(volume));
  const ReferenceWeight w = reference_weight("pi" + family, disc.cloud.dim);
  return shepard_volumes(
      disc, [&disc, &w](Index j) { return [&w, h = disc.neighbours.radius(j)](Real r) { return w.value(r, h); }; },
      "gpm (weight pi" + family + ")");
}

namespace {

class Gpm final : public Method {
 public:
  explicit Gpm(const MethodOptions& o)
      : info_(gpm_info()),
        family_(o.get_choice("weight", "2", {"1", "2", "3"})),
        volume_(o.get_choice("volume", "lattice", {"lattice", "shepard", "uniform", "voronoi", "vrsph"})),
        mean_(read_pair_mean(o)) {}
  const MethodInfo& info() const override { return info_; }
  int reach() const override { return volume_ == "vrsph" ? 3 : volume_ == "shepard" || volume_ == "voronoi" ? 2 : 1; }
  // Rows read distances, pair vectors and the neighbours' volumes and coefficient values; every
  // volume reads the list or the cloud as a periodic box allows (Shepard sums over each
  // neighbour's own list, VRSPH's point volumes over pair vectors, Voronoi cells and |Ω|/N over
  // the periodic box).
  bool reads_periodic_pairs(const StencilRequest& /*req*/) const override { return true; }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req, reads_periodic_pairs(req));
    const auto& cloud = disc.cloud;
    const int d = cloud.dim;
    const ReferenceWeight value_w = reference_weight("pi" + family_, d);
    const ReferenceWeight grad_w = reference_weight("grad" + family_, d);
    const ReferenceWeight lap_w = reference_weight("delta" + family_, d);
    const std::vector<Real> V = gpm_volumes(disc, volume_, family_);
    Stencil s = make_stencil_pattern(disc.neighbours, req.kind, d, info_.name);
#pragma omp parallel for schedule(dynamic, 256)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (!row_requested(cloud, req, i)) continue;
      const Real h = disc.neighbours.radius(i);
      const auto nbr = disc.neighbours.of(i);
      const auto dist = disc.neighbours.distances_of(i);
      for (std::size_t k = 0; k < nbr.size(); ++k) {
        const auto j = static_cast<std::size_t>(nbr[k]);
        const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)));
        const Real r = dist[k];
        switch (req.kind) {
          case OperatorKind::Value: s.values[0][slot] = gpm::value_weight(V[j], value_w.value(r, h)); break;
          case OperatorKind::Laplacian: s.values[0][slot] = gpm::laplacian_weight(d, V[j], lap_w.value(r, h), r); break;
          case OperatorKind::DivAGrad: {
            const Field& a = *req.coefficient;
            // (a_i + a_j)/2 times the Laplacian weight (the Morris pair form)
            s.values[0][slot] = 0.5 * pair_sum(mean_, a[i], a[static_cast<Eigen::Index>(j)]) * gpm::laplacian_weight(d, V[j], lap_w.value(r, h), r);
            break;
          }
          default: {
            const Vec3 g = gpm::gradient_weight(d, V[j], grad_w.value(r, h), r,
                                                disc.neighbour_position(i, static_cast<Index>(k)) - cloud.positions[si]);
            store_pair_gradient(s, req.kind, d, slot, g);
          }
        }
      }
      if (req.kind == OperatorKind::Value)
        s.values[0][static_cast<std::size_t>(s.diag[si])] = gpm::value_weight(V[si], value_w.value(0, h));
    }
    if (req.kind != OperatorKind::Value) set_difference_diagonal(s);
    return s;
  }

 private:
  MethodInfo info_;
  std::string family_;
  std::string volume_;
  PairMean mean_;
};

}  // namespace

std::unique_ptr<Method> make_gpm(const MethodOptions& options) { return std::make_unique<Gpm>(options); }

}  // namespace vrsph
