// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How a study picks the kernel support radius ([QW] §4, METHODS §3.2, P15):
//   fixed     h = kappa dx                       (all published runs)
//   covering  h = kappa max(dx, r_N)             (r_N the exact covering radius; [QW]'s rule)
//   knn       h_i = kappa r_k(i) per particle    (r_k = distance to the k-th nearest particle;
//                                                 k = 2d by default, which is dx on a lattice)
#include <string>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

enum class SmoothingMode { Fixed, Covering, Knn };
/// "fixed" | "covering" | "knn"; throws ConfigError otherwise.
SmoothingMode parse_smoothing_mode(const std::string& name);
std::string to_string(SmoothingMode m);

struct SmoothingChoice {
  Real h = 0;                ///< the radius (Fixed/Covering) or the mean of the per-particle radii (Knn)
  std::vector<Real> radii;   ///< per-particle radii (Knn only)
  Real covering_radius = 0;  ///< r_N if it was computed (Covering), else 0
};

/// A support wider than the whole cloud (its diameter `extent`, ghosts excluded) makes
/// every particle a neighbour of every other: the operator is no longer local, kernel
/// sums are constants, the result is meaningless (100 % error) and the cost grows as
/// N^2. Throws ConfigError naming h and the h-factor.
/// kappa <= 0: h was given directly (no h-factor to name).
void check_support_is_local(Real h, Real extent, Real kappa);
/// Diameter of the bounding box of the non-ghost particles.
Real cloud_extent(const PointCloud& cloud);

/// knn <= 0 selects k = 2 d; knn < 0 and kappa <= 0 are ConfigErrors, and so is a
/// support wider than the cloud (check_support_is_local).
SmoothingChoice choose_smoothing(const PointCloud& cloud, Real dx, Real kappa, SmoothingMode mode, int knn = 0);

}  // namespace vrsph
