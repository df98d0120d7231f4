// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <numbers>
#include <unordered_map>
#include <vrsph/cloud/blue_noise.hpp>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/core/error.hpp>
#include "random.hpp"

namespace vrsph {

namespace {
// Points hashed by cells of side r: every point within r of x lies in the 3^d cells around
// x's cell. A hash map rather than an array over the bounding box, so that a thin shell
// (surface sampling) costs memory in proportion to its points, not to its box.
class CellHash {
 public:
  CellHash(int dim, Real r) : dim_(dim), r_(r), r2_(r * r) {}

  void insert(const Vec3& x) {
    cells_[key(cell_of(x))].push_back(x);
  }

  bool has_point_within_r(const Vec3& x) const {
    const auto c = cell_of(x);
    const int reach[3] = {1, dim_ > 1 ? 1 : 0, dim_ > 2 ? 1 : 0};
    for (long long dz = -reach[2]; dz <= reach[2]; ++dz)
      for (long long dy = -reach[1]; dy <= reach[1]; ++dy)
        for (long long dx = -reach[0]; dx <= reach[0]; ++dx) {
          const auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (const Vec3& p : it->second)
            if ((p - x).squaredNorm() < r2_) return true;
        }
    return false;
  }

 private:
  using Cell = std::array<long long, 3>;
  Cell cell_of(const Vec3& x) const {
    return {static_cast<long long>(std::floor(x[0] / r_)), static_cast<long long>(std::floor(x[1] / r_)),
            static_cast<long long>(std::floor(x[2] / r_))};
  }
  static std::uint64_t key(const Cell& c) {  // 21 bits per axis (wrapping is harmless: only a cache miss)
    const auto b = [](long long v) { return static_cast<std::uint64_t>(v) & 0x1FFFFFu; };
    return b(c[0]) | (b(c[1]) << 21) | (b(c[2]) << 42);
  }
  int dim_;
  Real r_, r2_;
  std::unordered_map<std::uint64_t, std::vector<Vec3>> cells_;
};

void check_radius(Real r) {
  check<ConfigError>(std::isfinite(r) && r > 0, "blue noise: the exclusion radius must be positive and finite, got ", r);
}
}  // namespace

Real blue_noise_radius_factor(int dim) {
  check<ConfigError>(dim >= 1 && dim <= 3, "blue noise: dimension must be 1, 2 or 3, got ", dim);
  // 1D: Renyi's parking constant (mean gap 1.34 r); 2D and 3D: measured densities of the
  // grown and the thinned sets (a unit square at spacing 0.01, a unit cube at 0.025).
  constexpr Real factor[3] = {0.75, 0.785, 0.83};
  return factor[dim - 1];
}

std::vector<Vec3> grow_blue_noise(int dim, Real r, const std::vector<Vec3>& seeds,
                                  const std::function<bool(const Vec3&)>& admissible, std::uint64_t seed, int attempts) {
  check_radius(r);
  check<ConfigError>(dim >= 1 && dim <= 3, "blue noise: dimension must be 1, 2 or 3, got ", dim);
  check<ConfigError>(attempts >= 1, "blue noise: at least one attempt per point is needed");
  CellHash grid(dim, r);
  for (const Vec3& s : seeds) grid.insert(s);
  std::deque<Vec3> active(seeds.begin(), seeds.end());
  std::vector<Vec3> out;
  std::uint64_t draw = 0;  // counter of the random stream: one per candidate
  while (!active.empty()) {
    const Vec3 centre = active.front();
    active.pop_front();
    for (int t = 0; t < attempts; ++t, ++draw) {
      // Uniform in the shell r <= |d| < 2r: radius by inverting the shell's volume fraction,
      // direction uniform on the sphere (circle, or +-1 in 1D).
      const Real u0 = detail::uniform01(seed, draw, 0), u1 = detail::uniform01(seed, draw, 1),
                 u2 = detail::uniform01(seed, draw, 2);
      const Real rho = r * std::pow(1 + u0 * (std::pow(2.0, dim) - 1), 1.0 / dim);
      Vec3 d = Vec3::Zero();
      if (dim == 1) {
        d[0] = u1 < 0.5 ? -1 : 1;
      } else if (dim == 2) {
        const Real phi = 2 * std::numbers::pi * u1;
        d = Vec3(std::cos(phi), std::sin(phi), 0);
      } else {
        const Real z = 2 * u1 - 1, phi = 2 * std::numbers::pi * u2, s = std::sqrt(std::max<Real>(0, 1 - z * z));
        d = Vec3(s * std::cos(phi), s * std::sin(phi), z);
      }
      const Vec3 x = centre + rho * d;
      if (!admissible(x) || grid.has_point_within_r(x)) continue;
      grid.insert(x);
      out.push_back(x);
      active.push_back(x);
    }
  }
  return out;
}

std::vector<std::size_t> thin_to_blue_noise(const std::vector<Vec3>& candidates, Real r, const std::vector<Vec3>& fixed,
                                            std::uint64_t seed) {
  check_radius(r);
  CellHash grid(3, r);  // the 27 cells around a point: right in any dimension (unused axes are 0)
  for (const Vec3& f : fixed) grid.insert(f);
  // A random visiting order: candidates sorted by a hash of (seed, index).
  std::vector<std::pair<std::uint64_t, std::size_t>> order(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) order[k] = {detail::splitmix64(seed ^ detail::splitmix64(k)), k};
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> kept;
  for (const auto& [h, k] : order) {
    if (grid.has_point_within_r(candidates[k])) continue;
    grid.insert(candidates[k]);
    kept.push_back(k);
  }
  return kept;
}

}  // namespace vrsph
