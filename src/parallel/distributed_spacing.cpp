// SPDX-License-Identifier: BSD-3-Clause
// estimate_spacing (point_cloud.cpp) of a cloud spread over ranks, for clouds without a
// known domain (users' files): the same statistics of the same per-particle distances,
// each computed by the particle's owner from its owned + halo particles.
#include <bit>
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/parallel/distributed_cloud.hpp>

namespace vrsph {

namespace {
// The value of order `m` (0-based) among every rank's non-negative values: bisection on
// the bit patterns, whose order is the values' order for non-negative doubles.
double order_statistic_over_ranks(const Communicator& comm, const std::vector<double>& values, long long m) {
  std::uint64_t lo = 0, hi = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::infinity());
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    const double v = std::bit_cast<double>(mid);
    long long at_most = 0;
    for (double x : values) at_most += x <= v;
    if (sum_over_ranks(comm, at_most) >= m + 1) hi = mid;
    else lo = mid + 1;
  }
  return std::bit_cast<double>(lo);
}

// k-th neighbour distances; "not found" (infinity) while the local cloud has too few particles.
std::vector<double> kth_or_infinity(const PointCloud& local, int k) {
  if (local.size() <= k) return std::vector<double>(static_cast<std::size_t>(local.size()), std::numeric_limits<double>::infinity());
  const std::vector<Real> d = kth_neighbour_distance(local, k);
  return {d.begin(), d.end()};
}

// Per owned particle, a distance that needs the particles within it: widens the halo until
// every owned value is at most the halo width (so no particle beyond it could change it).
// `value` returns one value per local particle, negative for "none" (not counted), and
// infinity for "not found within the halo".
std::vector<double> owned_values(const PointCloud& chunk, Real width, Real diagonal, const Communicator& comm,
                                 const std::function<std::vector<double>(const DistributedCloud&)>& value) {
  for (;;) {
    const DistributedCloud dc = distribute(chunk, width, comm);
    std::vector<double> all, mine;
    collective(comm, [&] { all = value(dc); });
    double worst = 0;
    for (std::size_t i = 0; i < all.size(); ++i)
      if (dc.owned[i] && all[i] >= 0) {
        mine.push_back(all[i]);
        worst = std::max(worst, all[i]);
      }
    worst = max_over_ranks(comm, worst);
    if (worst <= dc.halo_width) return mine;
    // Not found within the halo: at least the whole bounding box (then every particle is local).
    width = std::isfinite(worst) ? std::max(worst * (1 + 1e-9), 2 * width) : std::max(4 * width, diagonal);
  }
}
}  // namespace

Real estimate_spacing_over_ranks(const PointCloud& chunk, const Communicator& comm) {
  if (!comm.distributed()) return estimate_spacing(chunk);
  const Real given = max_over_ranks(comm, chunk.spacing);
  if (given > 0) return given;
  const long long n = sum_over_ranks(comm, static_cast<long long>(chunk.size()));
  const int dim = static_cast<int>(max_over_ranks(comm, static_cast<double>(chunk.size() ? chunk.dim : 0)));
  collective(comm, [&] {
    check<GeometryError>(n >= 2, "the cloud has only ", n,
                         " particle: no spacing, no neighbours, no operator (at least 2 distinct particles are needed)");
  });
  const Real measure = max_over_ranks(comm, chunk.size() ? chunk.domain.measure() : 0.0);
  if (measure > 0) {
    const long long inside = n - sum_over_ranks(comm, static_cast<long long>(chunk.count(Tag::Ghost)));
    return std::pow(measure / static_cast<Real>(std::max<long long>(inside, 1)), 1.0 / dim);
  }
  // The first halo width: a few mean spacings of the bounding box.
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const Vec3& x : chunk.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  Real box = 1, diagonal = 0;
  for (int k = 0; k < dim; ++k) {
    const Real side = std::max(max_over_ranks(comm, hi[k]) + max_over_ranks(comm, -lo[k]), 0.0);
    box *= side;
    diagonal += side * side;
  }
  diagonal = 1.01 * std::sqrt(diagonal) + 1e-300;
  const int k = dim == 1 ? 1 : dim == 2 ? 12 : 32;
  const Real width0 = 2 * std::pow(std::max(box, 1e-300) * (k + 1) / static_cast<Real>(n), 1.0 / dim);

  Real spacing = 0;
  if (dim == 1) {
    // The gap from each distinct position to the next larger one, counted at the particle of
    // that position with the smallest global id (duplicates are within any halo).
    const Real x_max = max_over_ranks(comm, hi[0]);
    const std::vector<double> gaps = owned_values(chunk, width0, diagonal, comm, [&](const DistributedCloud& dc) {
      const PointCloud& c = dc.local;
      std::vector<std::pair<Real, Index>> order;  // (x, global id), sorted
      for (Index i = 0; i < c.size(); ++i) order.emplace_back(c.positions[static_cast<std::size_t>(i)][0], dc.global_id[static_cast<std::size_t>(i)]);
      std::vector<std::size_t> perm(order.size());
      for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
      std::sort(perm.begin(), perm.end(), [&](std::size_t a, std::size_t b) { return order[a] < order[b]; });
      std::vector<double> gap(order.size(), -1);
      for (std::size_t r = 0; r < perm.size(); ++r) {
        const std::size_t i = perm[r];
        if (r > 0 && order[perm[r - 1]].first == order[i].first) continue;  // not the first of its position
        if (order[i].first == x_max) continue;                              // the largest: no gap
        std::size_t s = r + 1;
        while (s < perm.size() && order[perm[s]].first == order[i].first) ++s;
        gap[i] = s < perm.size() ? order[perm[s]].first - order[i].first : std::numeric_limits<double>::infinity();
      }
      return gap;
    });
    const long long count = sum_over_ranks(comm, static_cast<long long>(gaps.size()));
    spacing = count > 0 ? order_statistic_over_ranks(comm, gaps, count / 2) : 0;
  } else if (n <= 4 * k) {
    // Small clouds: the mean nearest-neighbour distance.
    const std::vector<double> nn = owned_values(chunk, width0, diagonal, comm, [&](const DistributedCloud& dc) {
      return kth_or_infinity(dc.local, 1);
    });
    double sum = 0;
    for (double d : nn) sum += d;
    spacing = sum_over_ranks(comm, sum) / static_cast<double>(n);
  } else {
    const std::vector<double> rk = owned_values(chunk, width0, diagonal, comm, [&](const DistributedCloud& dc) {
      return kth_or_infinity(dc.local, k);
    });
    const Real ball = dim == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
    spacing = order_statistic_over_ranks(comm, rk, n / 2) * std::pow(ball / (k + 1), 1.0 / dim);
  }
  collective(comm, [&] {
    check<InputError>(spacing > 0, "every particle has a duplicate at distance 0 (each position occurs more than "
                      "once), or all are at one position: the cloud has no spacing; remove the duplicate particles");
  });
  return spacing;
}

}  // namespace vrsph
