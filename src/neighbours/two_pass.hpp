// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the count-then-fill driver shared by every search backend. A backend
// supplies `visit(i, r_i, emit)`, which calls emit(j, r2) for every candidate j that may
// lie within radius r_i of particle i (a superset is fine; the driver filters).
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph::detail {

std::vector<Real> resolve_radii(const PointCloud& cloud, const SearchParams& params);

/// GeometryError naming the first non-ghost particle whose row (offsets filled) has fewer
/// than `minimum` neighbours (its own entry not counted when `include_self`); with `rows`,
/// only the particles marked there (a rank's owned particles: a halo row may be cut).
inline void check_min_neighbours(const PointCloud& cloud, const NeighbourList& list, std::span<const Real> radii,
                                 Index minimum, bool include_self, std::span<const char> rows = {}) {
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost || (!rows.empty() && !rows[static_cast<std::size_t>(i)]))
      continue;
    const Index c = list.count(i) - (include_self ? 1 : 0);
    if (c < minimum) {
      const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
      throw GeometryError(concat("particle ", i, " at (", x[0], ", ", x[1], ", ", x[2], ") has ", c,
                                 " neighbours within radius ", radii[static_cast<std::size_t>(i)], " (need at least ",
                                 minimum, "); increase the smoothing radius or check the cloud"));
    }
  }
}

/// InputError naming the duplicate pair (a, b): the lowest pair within the duplicate tolerance
/// (`tolerance` times the support radius of the row that found it: at most the larger of the
/// pair's, `radius`). The tolerance is stated: a radius far above the spacing (an outlier
/// particle inflates an estimated spacing) makes distinct particles duplicates, and the message
/// then shows it.
[[noreturn]] inline void throw_duplicate(const PointCloud& cloud, long long a, long long b, Real tolerance, Real radius) {
  const Vec3& x = cloud.positions[static_cast<std::size_t>(a)];
  throw InputError(concat("duplicate particles ", a, " and ", b, " at (", x[0], ", ", x[1], ", ", x[2], "): distance ",
                          (cloud.positions[static_cast<std::size_t>(a)] - cloud.positions[static_cast<std::size_t>(b)]).norm(),
                          " is below the duplicate tolerance ", tolerance * radius, " (", tolerance,
                          " times the support radius ", radius, ")"));
}

/// Bytes per stored pair: the neighbour index and, if cached, the distance.
inline double neighbour_pair_bytes(const SearchParams& params) {
  return static_cast<double>(sizeof(Index) + (params.cache_distances ? sizeof(Real) : 0));
}

// A row's keys in ascending order. The candidates arrive in runs of ascending index (one per
// cell: the cells hold their particles in index order), so on a cloud numbered along a lattice
// each key lies about one place (2D) or nine places (3D, 175 a row) from where it belongs, and
// insertion sort costs the keys plus those shifts: a whole search took 0.80 (2D) and 0.75-0.93
// (3D) of its time with std::sort, which partitions first and mispredicts (10^6 perturbed
// particles, radius 3.6 spacings, one thread). On a shuffled cloud the shifts grow as the row's
// square (n / 4 a key): once they exceed 1.5 log2(n) a key so far (plus a slack of n / 2), the
// row goes to std::sort (shuffled: 2D 0.89, 3D 0.93 of std::sort's time). The keys are
// distinct (each holds its slot): either way gives the same order.
inline void sort_row_keys(std::uint64_t* key, std::uint32_t count) {
  const std::size_t per_key = 3 * static_cast<std::size_t>(std::bit_width(count)) / 2, slack = count / 2;
  std::size_t shifts = 0;
  for (std::uint32_t a = 1; a < count; ++a) {
    const std::uint64_t v = key[a];
    std::uint32_t b = a;
    for (; b > 0 && key[b - 1] > v; --b) key[b] = key[b - 1];
    key[b] = v;
    shifts += a - b;
    if (shifts > per_key * a + slack) {
      std::sort(key, key + count);
      return;
    }
  }
}

// `list`: a list whose arrays are reused (their capacity), e.g. the previous search of a
// moving cloud; its contents are overwritten.
template <class Visit>
NeighbourList two_pass_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                              Visit&& visit, NeighbourList list = {}) {
  const Index n = cloud.size();
  list.shifts.clear();
  list.offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  const Real dup_tol = params.duplicate_tolerance;
  std::atomic<long long> duplicate{std::numeric_limits<long long>::max()};  // encoded i * n + j

  // Pass 1: count.
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    const Real ri = radii[static_cast<std::size_t>(i)];
    const Real r2max = ri * ri, dup2 = dup_tol * dup_tol * r2max;
    Index count = 0;
    visit(i, ri, [&](Index j, Real r2) {
      if (j == i) {
        count += params.include_self ? 1 : 0;
        return;
      }
      if (r2 <= dup2) {
        const long long code = static_cast<long long>(std::min(i, j)) * n + std::max(i, j);
        long long cur = duplicate.load();
        while (code < cur && !duplicate.compare_exchange_weak(cur, code)) {
        }
      }
      count += r2 < r2max ? 1 : 0;
    });
    list.offsets[static_cast<std::size_t>(i) + 1] = count;
  }
  if (const long long code = duplicate.load(); code != std::numeric_limits<long long>::max())
    throw_duplicate(cloud, code / n, code % n, dup_tol,
                    std::max(radii[static_cast<std::size_t>(code / n)], radii[static_cast<std::size_t>(code % n)]));
  long long total = 0;
  for (Index i = 0; i < n; ++i) {
    total += list.offsets[static_cast<std::size_t>(i) + 1];
    check<ResourceError>(total <= std::numeric_limits<Index>::max(), "the neighbour list has more than ",
                         std::numeric_limits<Index>::max(), " pairs (", n, " particles): reduce the smoothing radius "
                         "(--h-factor) or the number of particles");
    list.offsets[static_cast<std::size_t>(i) + 1] = static_cast<Index>(total);
  }
  // The exact size is known now, before the big arrays are allocated.
  check_memory_estimate(static_cast<double>(total) * neighbour_pair_bytes(params),
                        concat("the neighbour list (", total, " pairs, ", total / std::max(n, 1), " per particle)"),
                        "reduce the smoothing radius (--h-factor) or the number of particles");
  // Too few neighbours: reported before filling, naming the first offender.
  check_min_neighbours(cloud, list, radii, params.min_neighbours, params.include_self);

  // Pass 2: fill, then sort each row by index so the output does not depend on the backend.
  resize_for_overwrite(list.indices, static_cast<std::size_t>(total));
  if (params.cache_distances)
    resize_for_overwrite(list.distances, static_cast<std::size_t>(total));
  else
    list.distances.clear();
#pragma omp parallel
  {
    // Per thread, grown to the most candidates a row has had and never shrunk. Every candidate
    // is written and only the kept ones advance `kept`: whether a candidate lies within the
    // radius is a coin toss the branch predictor loses (about half of a cell list's candidates),
    // and as a branch around the store it was most of this pass's time (perf, 10^6 2D particles).
    // The row is sorted by index as 64-bit keys (index, slot of its squared distance): sorting
    // (index, distance) pairs moved twice the bytes and compared pairs.
    std::vector<std::uint64_t> key;
    std::vector<Real> dist2;
#pragma omp for schedule(dynamic, 256)
    for (Index i = 0; i < n; ++i) {
      const Real ri = radii[static_cast<std::size_t>(i)];
      const Real r2max = ri * ri;
      std::uint32_t kept = 0;
      visit(i, ri, [&](Index j, Real r2) {
        if (kept == key.size()) {
          key.resize(2 * key.size() + 64);
          dist2.resize(key.size());
        }
        key[kept] = static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 32 | kept;
        dist2[kept] = r2;
        kept += (j == i ? params.include_self : r2 < r2max) ? 1 : 0;
      });
      sort_row_keys(key.data(), kept);
      auto k = static_cast<std::size_t>(list.offsets[static_cast<std::size_t>(i)]);
      for (std::uint32_t m = 0; m < kept; ++m, ++k) {
        list.indices[k] = static_cast<Index>(key[m] >> 32);
        if (params.cache_distances) list.distances[k] = std::sqrt(dist2[key[m] & 0xffffffffu]);
      }
    }
  }
  list.radii = std::move(radii);
  return list;
}

}  // namespace vrsph::detail
