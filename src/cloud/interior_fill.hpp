// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The interior particles of a geometry fill, shared by the polygon (polygon.cpp) and the closed
// surface (surface.cpp): the same lattice or blue-noise rule in 2D and 3D.
#include <cmath>
#include <cstdint>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/cloud/blue_noise.hpp>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/cloud/point_cloud.hpp>
#include "random.hpp"

namespace vrsph::detail {

/// Refuses a fill whose lattice (or surface sample) would exceed 2e9 points, with the count
/// it would have ("more than 1e308" when the spacing is so small that the count overflows).
inline void check_lattice_size(double points, Real spacing) {
  check<ResourceError>(points < 2e9, "a spacing of ", spacing, " would put ",
                       std::isfinite(points) ? concat(points) : std::string("more than 1e308"),
                       " lattice points over the geometry (at most 2e9): choose a larger spacing");
}

/// Appends Interior particles (zero normals) to `cloud`, which holds the boundary particles
/// with their normals: blue noise grown from those boundary particles (random stream
/// `blue_noise_seed`), or the lattice of the spacing from `lo` over [lo, hi], perturbed by
/// fill.delta (stream fill.seed, counter = lattice index); only points where admissible(x).
template <class Admissible>
void add_interior_particles(PointCloud& cloud, const Vec3& lo, const Vec3& hi, const GeometryFill& f,
                            std::uint64_t blue_noise_seed, const Admissible& admissible) {
  const int dim = cloud.dim;
  const auto put = [&cloud](const Vec3& x) {
    cloud.positions.push_back(x);
    cloud.tags.push_back(Tag::Interior);
    cloud.normals.push_back(Vec3::Zero());
  };
  check<ConfigError>(f.parts >= 1 && f.part >= 0 && f.part < f.parts, "geometry fill: part ", f.part, " of ", f.parts);
  if (f.pattern == FillPattern::BlueNoise) {
    check<ConfigError>(f.parts == 1, "a blue-noise fill grows from the whole boundary: it cannot be made in parts");
    const std::vector<Vec3> seeds = cloud.positions;
    for (const Vec3& x : grow_blue_noise(dim, blue_noise_radius_factor(dim) * f.spacing, seeds, admissible, blue_noise_seed))
      put(x);
    return;
  }
  const auto n = [&](int k) { return k < dim ? static_cast<long long>((hi[k] - lo[k]) / f.spacing) + 1 : 0; };
  const long long nx = n(0), ny = n(1), nz = n(2);
  // This part's layers of the outermost axis (the last one): [layers p / P, layers (p + 1) / P).
  const long long layers = (dim == 3 ? nz : ny) + 1;
  const long long l0 = layers * f.part / f.parts, l1 = layers * (f.part + 1) / f.parts;
  for (long long kz = dim == 3 ? l0 : 0; kz <= (dim == 3 ? l1 - 1 : nz); ++kz)
    for (long long ky = dim == 3 ? 0 : l0; ky <= (dim == 3 ? ny : l1 - 1); ++ky)
      for (long long kx = 0; kx <= nx; ++kx) {
        Vec3 x = lo + f.spacing * Vec3(static_cast<Real>(kx), static_cast<Real>(ky), static_cast<Real>(kz));
        if (f.delta > 0) {
          const auto id = static_cast<std::uint64_t>((kz * (ny + 1) + ky) * (nx + 1) + kx);
          for (int k = 0; k < dim; ++k)
            x[k] += f.delta * f.spacing * (2 * uniform01(f.seed, id, static_cast<std::uint64_t>(k)) - 1);
        }
        if (admissible(x)) put(x);
      }
}

}  // namespace vrsph::detail
