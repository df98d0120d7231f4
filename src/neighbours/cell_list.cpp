// SPDX-License-Identifier: BSD-3-Clause
// Cell-list backend: counting sort of particles into cells no smaller than the
// largest radius, then a 3^d-cell scan per particle.
#include <algorithm>
#include <array>
#include <cmath>
#include "two_pass.hpp"

namespace vrsph::detail {

namespace {
struct CellGrid {
  int dim = 1;
  Vec3 lo = Vec3::Zero();
  Real cell = 1;
  std::array<long long, 3> cells{1, 1, 1};
  std::vector<Index> start;  // size ncells + 1
  std::vector<Index> order;  // particle ids sorted by cell
  std::vector<Vec3> sorted;  // positions in that order (cache-friendly scans)

  std::array<long long, 3> coord(const Vec3& x) const {
    std::array<long long, 3> c{0, 0, 0};
    for (int k = 0; k < dim; ++k)
      c[static_cast<std::size_t>(k)] = std::clamp(static_cast<long long>(std::floor((x[k] - lo[k]) / cell)), 0LL,
                                                  cells[static_cast<std::size_t>(k)] - 1);
    return c;
  }
  long long linear(const std::array<long long, 3>& c) const { return (c[2] * cells[1] + c[1]) * cells[0] + c[0]; }
};

// A dense grid of cells of side max_radius pays off when it has not many more cells
// than particles. Counted in floating point: the extent over the radius may be 1e300
// (one far-away particle, or a tiny radius), far beyond any integer type.
bool dense_grid_fits(const PointCloud& cloud, Real max_radius, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
  hi = -lo;
  for (const Vec3& x : cloud.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  double total = 1;
  for (int k = 0; k < cloud.dim; ++k) total *= std::floor((hi[k] - lo[k]) / max_radius) + 1;
  return std::isfinite(total) && total <= 8.0 * static_cast<double>(cloud.size()) + 1024;
}

CellGrid build_grid(const PointCloud& cloud, Real max_radius, const Vec3& lo, const Vec3& hi) {
  CellGrid g;
  g.dim = cloud.dim;
  g.lo = lo;
  g.cell = max_radius;
  const auto n = static_cast<long long>(cloud.size());
  for (int k = 0; k < g.dim; ++k)
    g.cells[static_cast<std::size_t>(k)] = static_cast<long long>(std::floor((hi[k] - lo[k]) / g.cell)) + 1;
  const long long ncells = g.cells[0] * g.cells[1] * g.cells[2];
  g.start.assign(static_cast<std::size_t>(ncells) + 1, 0);
  std::vector<long long> cell_of(static_cast<std::size_t>(n));
  for (long long i = 0; i < n; ++i) {
    cell_of[static_cast<std::size_t>(i)] = g.linear(g.coord(cloud.positions[static_cast<std::size_t>(i)]));
    ++g.start[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)]) + 1];
  }
  for (long long c = 0; c < ncells; ++c) g.start[static_cast<std::size_t>(c) + 1] += g.start[static_cast<std::size_t>(c)];
  g.order.resize(static_cast<std::size_t>(n));
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (long long i = 0; i < n; ++i)
    g.order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)])]++)] =
        static_cast<Index>(i);
  g.sorted.resize(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < g.order.size(); ++k) g.sorted[k] = cloud.positions[static_cast<std::size_t>(g.order[k])];
  return g;
}
}  // namespace

NeighbourList kd_tree_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                             NeighbourList storage);

NeighbourList cell_list_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                               NeighbourList storage) {
  const Real max_radius = *std::max_element(radii.begin(), radii.end());
  Vec3 lo, hi;
  // Clouds with far-away outliers or radii tiny against their extent would need a
  // grid of mostly empty cells (or more cells than any integer counts): the k-d tree
  // handles any finite extent in O(N log N) with memory O(N).
  if (!dense_grid_fits(cloud, max_radius, lo, hi)) return kd_tree_search(cloud, std::move(radii), params, std::move(storage));
  const CellGrid g = build_grid(cloud, max_radius, lo, hi);
  auto visit = [&](Index i, auto&& emit) {
    const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
    const auto c = g.coord(xi);
    std::array<long long, 3> from{0, 0, 0}, to{0, 0, 0};
    for (std::size_t k = 0; k < static_cast<std::size_t>(g.dim); ++k) {
      from[k] = std::max(c[k] - 1, 0LL);
      to[k] = std::min(c[k] + 1, g.cells[k] - 1);
    }
    for (long long cz = from[2]; cz <= to[2]; ++cz)
      for (long long cy = from[1]; cy <= to[1]; ++cy)
        for (long long cx = from[0]; cx <= to[0]; ++cx) {
          const long long cell = g.linear({cx, cy, cz});
          const Index b = g.start[static_cast<std::size_t>(cell)], e = g.start[static_cast<std::size_t>(cell) + 1];
          for (Index p = b; p < e; ++p) emit(g.order[static_cast<std::size_t>(p)], (g.sorted[static_cast<std::size_t>(p)] - xi).squaredNorm());
        }
  };
  return two_pass_search(cloud, std::move(radii), params, visit, std::move(storage));
}

}  // namespace vrsph::detail
