#include <algorithm>
#include <cmath>
#include <numeric>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
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

SmoothingChoice choose_smoothing(const PointCloud& cloud, Real dx, Real kappa, SmoothingMode mode, int knn) {
  check<InputError>(std::isfinite(kappa) && kappa > 0, "h-factor must be positive, got ", kappa);
  check<InputError>(std::isfinite(dx) && dx > 0, "particle spacing must be positive, got ", dx);
  SmoothingChoice c;
  switch (mode) {
    case SmoothingMode::Fixed:
      c.h = kappa * dx;
      break;
    case SmoothingMode::Covering:
      c.covering_radius = covering_radius(cloud).radius;
      c.h = kappa * std::max(dx, c.covering_radius);
      break;
    case SmoothingMode::Knn: {
      const int k = knn > 0 ? knn : 2 * cloud.dim;
      c.radii = kth_neighbour_distance(cloud, k);
      for (auto& r : c.radii) r *= kappa;
      c.h = std::accumulate(c.radii.begin(), c.radii.end(), 0.0) / static_cast<Real>(c.radii.size());
      break;
    }
  }
  return c;
}

}  // namespace vrsph
