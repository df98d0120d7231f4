// SPDX-License-Identifier: BSD-3-Clause
// Cell-list backend: counting sort of particles into cells of half the largest radius (or the
// whole radius where half cells would hold too few particles, or be too many), then per
// particle the strips of cells its disc or ball reaches.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include "two_pass.hpp"

namespace vrsph::detail {

namespace {
struct CellGrid {
  int dim = 1;
  int reach = 1;  // cells per largest radius: a particle's neighbours lie within `reach` cells of its own
  Vec3 lo = Vec3::Zero();
  Real cell = 1;
  Vec3 margin = Vec3::Zero();  // per axis: what rounding may misplace a particle by, against its cell's faces
  std::array<long long, 3> cells{1, 1, 1};
  std::vector<Index> start;  // size ncells + 1
  std::vector<Index> order;  // particle ids sorted by cell
  std::vector<Vec3> sorted;  // positions in that order (cache-friendly scans)

  // The cell of coordinate x along axis k, clamped to the grid: floor((x - lo) / cell) by a
  // truncation where that is the floor (0 <= v below the last cell), since the clamp decides
  // every other case. (std::floor is a call into libm on baseline x86-64, which has no rounding
  // instruction: 2-3 % of a search's time, measured.)
  long long coord(Real x, int k) const {
    const Real v = (x - lo[k]) / cell;
    const long long last = cells[static_cast<std::size_t>(k)] - 1;
    if (!(v > 0)) return 0;
    return v >= static_cast<Real>(last) ? last : static_cast<long long>(v);
  }
  std::array<long long, 3> coord(const Vec3& x) const {
    std::array<long long, 3> c{0, 0, 0};
    for (int k = 0; k < dim; ++k) c[static_cast<std::size_t>(k)] = coord(x[k], k);
    return c;
  }
  long long linear(long long cx, long long cy, long long cz) const { return (cz * cells[1] + cy) * cells[0] + cx; }
  // The distance from x (on axis k, in cell c0) to the slab of cells c along that axis, less
  // the margin: 0 inside c0's own slab.
  Real gap(Real x, int k, long long c0, long long c) const {
    const Real g = c < c0 ? x - (lo[k] + static_cast<Real>(c + 1) * cell) : c > c0 ? lo[k] + static_cast<Real>(c) * cell - x : 0;
    return std::max<Real>(0, g - margin[k]);
  }
};

// The number of cells of side `cell` a dense grid over the cloud's box needs, in floating point:
// the extent over the cell may be 1e300 (one far-away particle, or a tiny radius), far beyond
// any integer type.
double dense_cells(const PointCloud& cloud, Real cell, const Vec3& lo, const Vec3& hi) {
  double total = 1;
  for (int k = 0; k < cloud.dim; ++k) total *= std::floor((hi[k] - lo[k]) / cell) + 1;
  return total;
}

CellGrid build_grid(const PointCloud& cloud, Real max_radius, int reach, const Vec3& lo, const Vec3& hi) {
  CellGrid g;
  g.dim = cloud.dim;
  g.reach = reach;
  g.lo = lo;
  g.cell = max_radius / reach;
  const auto n = static_cast<long long>(cloud.size());
  for (int k = 0; k < g.dim; ++k) {
    g.cells[static_cast<std::size_t>(k)] = static_cast<long long>(std::floor((hi[k] - lo[k]) / g.cell)) + 1;
    // floor((x - lo) / cell) and lo + c * cell each round by a few ulps of the coordinates'
    // magnitude: a gap is trusted only beyond that (a superset of candidates is harmless).
    g.margin[k] = 64 * std::numeric_limits<Real>::epsilon() * (std::abs(lo[k]) + std::abs(hi[k]) + g.cell);
  }
  const long long ncells = g.cells[0] * g.cells[1] * g.cells[2];
  g.start.assign(static_cast<std::size_t>(ncells) + 1, 0);
  std::vector<long long> cell_of(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
  for (long long i = 0; i < n; ++i) {
    const auto c = g.coord(cloud.positions[static_cast<std::size_t>(i)]);
    cell_of[static_cast<std::size_t>(i)] = g.linear(c[0], c[1], c[2]);
  }
  for (long long i = 0; i < n; ++i) ++g.start[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)]) + 1];
  for (long long c = 0; c < ncells; ++c) g.start[static_cast<std::size_t>(c) + 1] += g.start[static_cast<std::size_t>(c)];
  g.order.resize(static_cast<std::size_t>(n));
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (long long i = 0; i < n; ++i)
    g.order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)])]++)] =
        static_cast<Index>(i);
  g.sorted.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
  for (long long k = 0; k < n; ++k)
    g.sorted[static_cast<std::size_t>(k)] = cloud.positions[static_cast<std::size_t>(g.order[static_cast<std::size_t>(k)])];
  return g;
}
}  // namespace

NeighbourList kd_tree_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                             NeighbourList storage);

NeighbourList cell_list_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                               NeighbourList storage) {
  const Real max_radius = *std::max_element(radii.begin(), radii.end());
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const Vec3& x : cloud.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  // Cells of half the radius: the strips a particle scans cover about 1.7 times fewer
  // candidates than the 3^d cells of a whole radius (2D: ~5.4 r^2 against 9 r^2 of area), but
  // there are more strips (2D 5 against 3, 3D 25 against 9), each with its own bounds. Half
  // cells paid off (perturbed lattices, 2D 1.6e5 and 10^6, 3D 2.3e5 particles, one thread)
  // from about 0.5 particles a half cell in 2D and 3 in 3D; with fewer, the strips' overhead
  // outweighed the candidates saved (3D, 1 a half cell: 0.80 s against 0.64 s).
  // A dense grid pays off while it has not many more cells than particles; clouds with
  // far-away outliers or radii tiny against their extent would need mostly empty cells (or
  // more cells than any integer counts): the k-d tree handles any finite extent in
  // O(N log N) with memory O(N).
  const auto n = static_cast<double>(cloud.size());
  const double budget = 8.0 * n + 1024, half_cell_density = cloud.dim == 3 ? 3.0 : cloud.dim == 2 ? 0.5 : 0.0;
  int reach = 0;
  if (const double cells = dense_cells(cloud, max_radius / 2, lo, hi);
      std::isfinite(cells) && cells <= budget && n >= half_cell_density * cells)
    reach = 2;
  else if (const double whole = dense_cells(cloud, max_radius, lo, hi); std::isfinite(whole) && whole <= budget)
    reach = 1;
  if (reach == 0) return kd_tree_search(cloud, std::move(radii), params, std::move(storage));
  const CellGrid g = build_grid(cloud, max_radius, reach, lo, hi);
  // Per row of cells (fixed y and z) within reach, the run of cells along x that the ball of
  // radius r_i can touch: one contiguous range of the sorted particles.
  auto visit = [&](Index i, Real ri, auto&& emit) {
    const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
    const auto c = g.coord(xi);
    std::array<long long, 3> from{0, 0, 0}, to{0, 0, 0};
    for (std::size_t k = 0; k < static_cast<std::size_t>(g.dim); ++k) {
      from[k] = std::max(c[k] - g.reach, 0LL);
      to[k] = std::min(c[k] + g.reach, g.cells[k] - 1);
    }
    const Real r2 = ri * ri;
    for (long long cz = from[2]; cz <= to[2]; ++cz) {
      const Real gz = g.dim > 2 ? g.gap(xi[2], 2, c[2], cz) : 0;
      if (gz * gz >= r2) continue;
      for (long long cy = from[1]; cy <= to[1]; ++cy) {
        const Real gy = g.dim > 1 ? g.gap(xi[1], 1, c[1], cy) : 0;
        const Real rest = r2 - gz * gz - gy * gy;
        if (rest <= 0) continue;
        const Real w = std::sqrt(rest) + g.margin[0];
        const long long xa = std::max(from[0], g.coord(xi[0] - w, 0)), xb = std::min(to[0], g.coord(xi[0] + w, 0));
        if (xa > xb) continue;
        const Index b = g.start[static_cast<std::size_t>(g.linear(xa, cy, cz))];
        const Index e = g.start[static_cast<std::size_t>(g.linear(xb, cy, cz)) + 1];
        for (Index p = b; p < e; ++p) emit(g.order[static_cast<std::size_t>(p)], (g.sorted[static_cast<std::size_t>(p)] - xi).squaredNorm());
      }
    }
  };
  return two_pass_search(cloud, std::move(radii), params, visit, std::move(storage));
}

}  // namespace vrsph::detail
