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

/// knn <= 0 selects k = 2 d.
SmoothingChoice choose_smoothing(const PointCloud& cloud, Real dx, Real kappa, SmoothingMode mode, int knn = 0);

}  // namespace vrsph
