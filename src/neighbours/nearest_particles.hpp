// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The nearest particle of each query point (k-d tree; defined in kd_tree.cpp). Private to the
// library: the covering radius scores its candidates with it, the periodic Voronoi cells find
// an image's original.
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph::detail {
void nearest_particles(const PointCloud& cloud, const std::vector<Vec3>& queries, std::vector<Real>& dist,
                       std::vector<Index>& index);
}  // namespace vrsph::detail
