// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A Neumann normal that points into the domain turns every flux row's sign: the solve would
// run and return a wrong field. The neighbours tell the side: an outward normal has them
// behind it (mean cosine about -0.6 on a flat wall), an inward one in front of it (+0.6).
#include <functional>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>

namespace vrsph::detail {

/// Throws InputError for the first Neumann row (rows[i] != 0) whose neighbours lie, on
/// average, clearly on the side its normal points to. `id` maps a local index to the one a
/// message should name (the global id in a distributed run).
inline void check_outward_normals(const PointCloud& cloud, const NeighbourList& nl, const std::vector<char>& rows,
                                  const std::function<long long(Index)>& id) {
  constexpr Real kInwardMeanCosine = 0.25;
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (!rows[si] || cloud.tags[si] != Tag::Neumann || nl.count(i) == 0) continue;
    const Vec3& x = cloud.positions[si];
    const Vec3& n = cloud.normals[si];
    Real cosines = 0;
    Index ahead = 0;
    for (const Index j : nl.of(i)) {
      const Vec3 d = cloud.positions[static_cast<std::size_t>(j)] - x;
      const Real r = d.norm();
      if (r == 0) continue;
      cosines += d.dot(n) / r;
      ahead += d.dot(n) > 0;
    }
    if (cosines <= kInwardMeanCosine * static_cast<Real>(nl.count(i))) continue;
    throw InputError(concat("Neumann particle ", id(i), " at (", x[0], ", ", x[1], ", ", x[2], "): its normal (", n[0],
                            ", ", n[1], ", ", n[2], ") points into the domain (", ahead, " of its ", nl.count(i),
                            " neighbours lie on the side it points to); normals must point out of the domain"));
  }
}

}  // namespace vrsph::detail
