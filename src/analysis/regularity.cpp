// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <vrsph/analysis/regularity.hpp>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/particle_volumes.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

RegularityReport regularity(const PointCloud& cloud, const RegularityOptions& o) {
  validate(cloud);
  RegularityReport r;
  r.covering = covering_radius(cloud);
  PointCloud inside;
  inside.dim = cloud.dim;
  inside.domain = cloud.domain;
  inside.spacing = cloud.spacing;
  for (Index i = 0; i < cloud.size(); ++i)
    if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Ghost)
      inside.add(cloud.positions[static_cast<std::size_t>(i)], cloud.tags[static_cast<std::size_t>(i)]);
  r.particles = inside.size();
  r.spacing = estimate_spacing(inside);
  r.h = o.h > 0 ? o.h : 3 * r.spacing;
  r.c0 = o.c0;
  check<ConfigError>(std::isfinite(r.h) && r.h > 0, "the support radius h must be positive, got ", o.h);
  check<ConfigError>(std::isfinite(o.c0) && o.c0 > 0, "the regularity constant c0 must be positive, got ", o.c0);
  const auto cells = voronoi_cell_measures(inside);
  SearchParams sp;
  sp.radius = r.h;
  sp.min_neighbours = 0;
  const NeighbourList nl = o.volumes == ParticleVolumes::Vrsph ? find_neighbours(inside, sp) : NeighbourList{};
  const auto volumes = particle_volumes({inside, nl, KernelType::CubicSpline, r.spacing}, o.volumes);
  r.deviation = voronoi_deviation(inside, volumes, cells, o.deviation);
  // h^m >= c0 (r + d)  <=>  m <= ln(c0 (r + d)) / ln h  (h < 1).
  const Real target = o.c0 * (r.covering.radius + r.deviation.value);
  r.order = r.h < 1 && target > 0 ? std::max(0.0, std::log(target) / std::log(r.h)) : 0;
  for (int n : {1, 3})
    for (const char* op : {"interpolant", "gradient", "laplacian"}) {
      const Real k = std::string(op) == "laplacian" ? 2 : 1;
      r.predicted.push_back({op, n, std::min(r.order - k, static_cast<Real>(n + 1))});
    }
  return r;
}

}  // namespace vrsph
