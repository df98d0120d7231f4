// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/user_list.hpp>
#include "../core/first_failure.hpp"
#include "two_pass.hpp"

namespace vrsph {

namespace {
void check_offsets(std::span<const Index> offsets, std::size_t entries, Index n) {
  check<InputError>(offsets.size() == static_cast<std::size_t>(n) + 1, "neighbour list: ", offsets.size(),
                    " row offsets for ", n, " particles (", n + 1, " expected)");
  check<InputError>(offsets[0] == 0, "neighbour list: the first row offset is ", offsets[0], ", not 0");
  for (Index i = 0; i < n; ++i)
    check<InputError>(offsets[static_cast<std::size_t>(i) + 1] >= offsets[static_cast<std::size_t>(i)],
                      "neighbour list: the row offsets decrease at particle ", i);
  check<InputError>(static_cast<std::size_t>(offsets.back()) == entries, "neighbour list: the offsets end at ",
                    offsets.back(), " but ", entries, " indices are given");
}
// The image of x_j that x_i sees on a periodic box (the nearest along each periodic axis; the
// only one within a support radius below half the period): its shift code, no_shift otherwise.
std::uint8_t nearest_image(const Domain& d, const Vec3& xi, const Vec3& xj) {
  std::array<int, 3> s{};
  for (int k = 0; k < std::min(d.dim, 3); ++k)
    if (d.periodic[static_cast<std::size_t>(k)]) {
      const Real v = xj[k] - xi[k], half = 0.5 * d.period(k);
      s[static_cast<std::size_t>(k)] = v > half ? -1 : v < -half ? 1 : 0;
    }
  return shift_code(s[0], s[1], s[2]);
}
}  // namespace

NeighbourList neighbour_list_from(const PointCloud& cloud, const UserNeighbours& user) {
  const Index n = cloud.size();
  check_offsets(user.offsets, user.indices.size(), n);
  check<InputError>(user.distances.empty() || user.distances.size() == user.indices.size(), "neighbour list: ",
                    user.distances.size(), " distances for ", user.indices.size(), " neighbour entries");
  check<InputError>(user.radii.size() == 1 || user.radii.size() == static_cast<std::size_t>(n), "neighbour list: ",
                    user.radii.size(), " support radii for ", n, " particles (give one, or one per particle)");
  NeighbourList nl;
  const bool periodic = cloud.domain.any_periodic();
  nl.radii.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const Real h = user.radii[user.radii.size() == 1 ? 0 : static_cast<std::size_t>(i)];
    check<InputError>(std::isfinite(h) && h > 0, "neighbour list: the support radius of particle ", i, " is ", h,
                      " (it must be positive and finite)");
    nl.radii[static_cast<std::size_t>(i)] = h;
  }
  // A periodic box: each pair's vector to the nearest image (as the search stores it, with its
  // shift code); the period must exceed twice the largest radius and the particles lie in the box.
  if (periodic) check_periodic_cloud(cloud, *std::max_element(nl.radii.begin(), nl.radii.end()));
  const auto image = [&](Index i, Index j, std::uint8_t& code) {
    const Vec3& xj = cloud.positions[static_cast<std::size_t>(j)];
    code = periodic ? nearest_image(cloud.domain, cloud.positions[static_cast<std::size_t>(i)], xj) : no_shift;
    return code == no_shift ? xj : Vec3(xj + periodic_shift(cloud.domain, code));
  };
  // As the search refuses it: a particle without neighbours has no row (SearchParams's default);
  // candidates are counted once they are filtered.
  nl.offsets.assign(user.offsets.begin(), user.offsets.end());
  if (!user.candidates) detail::check_min_neighbours(cloud, nl, nl.radii, user.min_neighbours, false);
  // Pass 1, rows in parallel: each entry checked, its distance and image found, and (candidates)
  // whether it lies within the row's radius; the rows' kept counts.
  const std::size_t entries = user.indices.size();
  std::vector<Real> distance(entries);
  std::vector<std::uint8_t> code(entries, no_shift);
  std::vector<char> keep(entries, 1);
  std::vector<Index> count(static_cast<std::size_t>(n), 0);
  detail::FirstFailure error;
#pragma omp parallel for schedule(dynamic, 1024)
  for (Index i = 0; i < n; ++i) {
    try {
      const auto si = static_cast<std::size_t>(i);
      const auto begin = static_cast<std::size_t>(user.offsets[si]), end = static_cast<std::size_t>(user.offsets[si + 1]);
      const Vec3& xi = cloud.positions[si];
      const Real h = nl.radii[si];
      for (std::size_t k = begin; k < end; ++k) {
        const Index j = user.indices[k];
        check<InputError>(j >= 0 && j < n, "neighbour list: row ", i, " lists particle ", j, ", outside 0..", n - 1);
        check<InputError>(j != i, "neighbour list: row ", i, " lists the particle itself");
        // As the search computes it (the square root of the squared distance), so that a list
        // found by find_neighbours comes back bitwise equal.
        const Real r2 = (image(i, j, code[k]) - xi).squaredNorm(), r = std::sqrt(r2);
        distance[k] = r;
        if (user.candidates && !(r2 < h * h)) {
          keep[k] = 0;
          continue;
        }
        check<InputError>(r2 < h * h, "neighbour list: particle ", j, " in row ", i, " is at distance ", r,
                          ", not within the row's support radius ", h);
        const Real pair_h = std::max(h, nl.radii[static_cast<std::size_t>(j)]), tolerance = SearchParams{}.duplicate_tolerance;
        if (r2 <= tolerance * tolerance * pair_h * pair_h)
          detail::throw_duplicate(cloud, std::min(i, j), std::max(i, j), tolerance, pair_h);
        if (!user.distances.empty())
          check<InputError>(std::abs(user.distances[k] - r) <= 1e-9 * h, "neighbour list: the distance of particle ", j,
                            " in row ", i, " is given as ", user.distances[k], " but the positions give ", r);
        ++count[si];
      }
    } catch (...) {
      error.record(i);
    }
  }
  error.rethrow();
  nl.offsets[0] = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) nl.offsets[i + 1] = nl.offsets[i] + count[i];
  if (user.candidates) detail::check_min_neighbours(cloud, nl, nl.radii, user.min_neighbours, false);
  const auto total = static_cast<std::size_t>(nl.offsets.back());
  nl.indices.resize(total);
  nl.distances.resize(total);
  if (periodic) nl.shifts.resize(total);
  // Pass 2: each row's kept entries sorted by index into its place.
  struct Entry {
    Index j;
    Real r;
    std::uint8_t code;
    bool operator<(const Entry& o) const { return j < o.j; }
  };
#pragma omp parallel
  {
    std::vector<Entry> row;
#pragma omp for schedule(dynamic, 1024)
    for (Index i = 0; i < n; ++i) {
      try {
        const auto si = static_cast<std::size_t>(i);
        row.clear();
        for (auto k = static_cast<std::size_t>(user.offsets[si]); k < static_cast<std::size_t>(user.offsets[si + 1]); ++k)
          if (keep[k]) row.push_back({user.indices[k], distance[k], code[k]});
        std::sort(row.begin(), row.end());
        const auto at = static_cast<std::size_t>(nl.offsets[si]);
        for (std::size_t k = 0; k < row.size(); ++k) {
          check<InputError>(k == 0 || row[k].j != row[k - 1].j, "neighbour list: row ", i, " lists particle ", row[k].j,
                            " twice");
          nl.indices[at + k] = row[k].j;
          nl.distances[at + k] = row[k].r;
          if (periodic) nl.shifts[at + k] = row[k].code;
        }
      } catch (...) {
        error.record(i);
      }
    }
  }
  error.rethrow();
  // Pass 3: a pair within both radii belongs to both rows (gather lists: j in N(i) iff r_ij < h_i).
#pragma omp parallel for schedule(dynamic, 1024)
  for (Index i = 0; i < n; ++i) {
    try {
      for (std::size_t k = static_cast<std::size_t>(nl.offsets[static_cast<std::size_t>(i)]);
           k < static_cast<std::size_t>(nl.offsets[static_cast<std::size_t>(i) + 1]); ++k) {
        const Index j = nl.indices[k];
        const Real hj = nl.radius(j);
        std::uint8_t c = no_shift;
        if (!((image(i, j, c) - cloud.positions[static_cast<std::size_t>(i)]).squaredNorm() < hj * hj)) continue;
        const auto other = nl.of(j);
        check<InputError>(std::binary_search(other.begin(), other.end(), i), "neighbour list: row ", i, " lists particle ",
                          j, " but row ", j, " does not list ", i, " although they are ", nl.distances[k],
                          " apart, within both support radii (a broken or one-sided list)");
      }
    } catch (...) {
      error.record(i);
    }
  }
  error.rethrow();
  return nl;
}

}  // namespace vrsph
