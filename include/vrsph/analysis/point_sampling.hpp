// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Values of a particle field at arbitrary points (probes, centre-line profiles): a moving
// least-squares fit of a quadratic polynomial to the particles within a radius of each point,
// weighted by Wendland's C2 function of the distance. Exact on quadratics; second order (the
// fit's error is O(r³) per point) on smooth fields.
#include <span>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

/// values: N x m (one column per field component); points: the probes (components beyond the
/// cloud's dimension ignored); radius > 0. Returns points.size() x m. On a periodic box the
/// particles' minimum images are used. GeometryError naming the point when fewer particles than
/// the fit needs (6 in 2D, 10 in 3D, 3 in 1D) lie within the radius or they do not determine a
/// quadratic; InputError for mismatched shapes or non-finite points.
Eigen::MatrixXd sample_field(const PointCloud& cloud, const Eigen::MatrixXd& values, std::span<const Vec3> points,
                             Real radius);

}  // namespace vrsph
