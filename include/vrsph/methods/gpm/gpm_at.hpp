// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The generalized particle method's operators (2)–(4) of [IM] at arbitrary evaluation
// points x (particles or not): Pi_h v(x), nabla_h v(x), Delta_h v(x) from the particle
// values u_j, volumes V_j and the weights pi<k>, grad<k>, delta<k> (gpm_pairs.hpp).
// The differences in (3)–(4) need v(x) at the point itself: the caller passes it (the
// exact function in a truncation-error study, or e.g. Pi_h v(x) in an application).
#include <span>
#include <string>
#include <vector>
#include <Eigen/Core>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct GpmPointValues {
  Eigen::VectorXd value;      ///< Pi_h v at each point
  Eigen::MatrixXd gradient;   ///< points x dim
  Eigen::VectorXd laplacian;  ///< Delta_h v
  std::vector<Index> neighbours;  ///< particles within h of each point
};

/// family: "1" | "2" | "3". Throws InputError on size mismatches, ConfigError on an unknown
/// family, GeometryError naming the first point with no particle closer than h.
GpmPointValues gpm_at_points(const PointCloud& cloud, std::span<const Real> volumes, const std::string& family, Real h,
                             const std::vector<Vec3>& points, std::span<const Real> u, std::span<const Real> u_at_points);

}  // namespace vrsph
