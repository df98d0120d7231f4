// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/particle_volumes.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>

namespace vrsph {

ParticleVolumes parse_particle_volumes(const std::string& name) {
  if (name == "uniform") return ParticleVolumes::Uniform;
  if (name == "voronoi") return ParticleVolumes::Voronoi;
  if (name == "vrsph") return ParticleVolumes::Vrsph;
  throw ConfigError(detail::concat("unknown particle volumes '", name, "' (uniform, voronoi or vrsph)"));
}

const char* particle_volumes_name(ParticleVolumes v) {
  return v == ParticleVolumes::Uniform ? "uniform" : v == ParticleVolumes::Voronoi ? "voronoi" : "vrsph";
}

std::vector<Real> particle_volumes(const Discretisation& disc, ParticleVolumes kind) {
  const PointCloud& cloud = disc.cloud;
  const auto n = static_cast<std::size_t>(cloud.size());
  // A rank's part (fewer particles than the whole cloud) is no whole periodic tessellation.
  if (kind == ParticleVolumes::Voronoi)
    return voronoi_cell_measures(cloud, disc.total_particles <= 0 || disc.total_particles == cloud.size());
  if (kind == ParticleVolumes::Uniform) {
    check<InputError>(cloud.domain.shape != Domain::Shape::None, "uniform volumes |Omega|/N need the cloud's domain");
    const Real total = disc.total_particles > 0 ? disc.total_particles : static_cast<Real>(n);
    return std::vector<Real>(n, cloud.domain.measure() / total);
  }
  const NeighbourList& nl = disc.neighbours;
  check<InputError>(nl.size() == cloud.size(), "vrsph particle volumes need the cloud's neighbour lists");
  const ReconstructedVolumes rv = reconstruct_volumes(disc, MomentConditions::Laplace);
  std::vector<Real> sum(n, 0), count(n, 0);
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto nbr = nl.of(i);
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      sum[static_cast<std::size_t>(nbr[k])] += rv.v[static_cast<std::size_t>(nl.offsets[static_cast<std::size_t>(i)]) + k];
      count[static_cast<std::size_t>(nbr[k])] += 1;
    }
  }
  for (std::size_t j = 0; j < n; ++j) sum[j] = count[j] > 0 ? sum[j] / count[j] : 0;
  return sum;
}

}  // namespace vrsph
