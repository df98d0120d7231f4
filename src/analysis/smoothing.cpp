// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

SmoothingMode parse_smoothing_mode(const std::string& name) {
  if (name == "fixed") return SmoothingMode::Fixed;
  if (name == "covering") return SmoothingMode::Covering;
  if (name == "knn") return SmoothingMode::Knn;
  throw ConfigError("unknown smoothing-radius mode '" + name + "' (known: fixed, covering, knn)");
}

std::string to_string(SmoothingMode m) {
  switch (m) {
    case SmoothingMode::Fixed: return "fixed";
    case SmoothingMode::Covering: return "covering";
    case SmoothingMode::Knn: return "knn";
  }
  return "?";
}

Real cloud_extent(const PointCloud& cloud) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost) continue;
    lo = lo.cwiseMin(cloud.positions[static_cast<std::size_t>(i)]);
    hi = hi.cwiseMax(cloud.positions[static_cast<std::size_t>(i)]);
  }
  return lo.allFinite() ? (hi - lo).norm() : std::numeric_limits<Real>::infinity();
}

void check_support_is_local(Real h, Real extent, Real kappa) {
  check<ConfigError>(!(h > extent), "support radius h = ", h, kappa > 0 ? detail::concat(" (h-factor ", kappa, ")") : "",
                     " exceeds the extent ", extent,
                     " of the whole cloud: every particle would see every other, so the operator is not local and "
                     "its result meaningless; use an h-factor of a few particle spacings (typically 2 to 4)");
}

SmoothingChoice choose_smoothing(const PointCloud& cloud, Real dx, Real kappa, SmoothingMode mode, int knn) {
  check<ConfigError>(std::isfinite(kappa) && kappa > 0, "h-factor must be positive and finite, got ", kappa);
  check<InputError>(std::isfinite(dx) && dx > 0, "particle spacing must be positive, got ", dx);
  check<ConfigError>(knn >= 0, "h-knn (k of the k-th neighbour) must be >= 1, or 0 for the default 2d; got ", knn);
  SmoothingChoice c;
  switch (mode) {
    case SmoothingMode::Fixed:
      c.h = kappa * dx;
      break;
    case SmoothingMode::Covering:
      check<ConfigError>(cloud.domain.shape != Domain::Shape::None,
                         "--h-mode covering needs a known domain (box or ball) for the covering radius; a cloud "
                         "without one (e.g. read from a file) cannot use it: use fixed or knn");
      c.covering_radius = covering_radius(cloud).radius;  // periodic: across the faces
      c.h = kappa * std::max(dx, c.covering_radius);
      break;
    case SmoothingMode::Knn: {
      const int k = knn > 0 ? knn : 2 * cloud.dim;
      c.radii = minimum_image_kth_neighbour_distance(cloud, k);  // plain without periodic axes
      for (auto& r : c.radii) r *= kappa;
      c.h = std::accumulate(c.radii.begin(), c.radii.end(), 0.0) / static_cast<Real>(c.radii.size());
      break;
    }
  }
  const Real h_max = c.radii.empty() ? c.h : *std::max_element(c.radii.begin(), c.radii.end());
  check_support_is_local(h_max, cloud_extent(cloud), kappa);
  return c;
}

}  // namespace vrsph
