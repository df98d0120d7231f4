// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// NeighbourList: for every particle i, the particles j with r_ij < radius_i, in
// compressed-sparse-row form. Row i is indices[offsets[i] .. offsets[i+1]),
// sorted ascending; self is excluded unless the search asked for it.
// If distances were cached, distances[k] = |x_i - x_j| for the same slot k.
#include <cstdint>
#include <span>
#include <vrsph/core/types.hpp>
#include <vrsph/core/uninitialized.hpp>

namespace vrsph {

struct NeighbourList {
  std::vector<Index> offsets{0};  ///< size N+1
  UninitVector<Index> indices;    ///< size offsets.back()
  UninitVector<Real> distances;   ///< empty, or one r_ij per entry of indices
  std::vector<Real> radii;        ///< search radius used for each row (size N)
  /// Periodic clouds: per entry, the image of j that i sees (periodic.hpp's shift code:
  /// x_j + periodic_shift(domain, code) - x_i is the pair's vector); empty otherwise.
  std::vector<std::uint8_t> shifts;

  Index size() const { return static_cast<Index>(offsets.size()) - 1; }
  Index count(Index i) const { return offsets[static_cast<std::size_t>(i) + 1] - offsets[static_cast<std::size_t>(i)]; }
  Index total() const { return offsets.back(); }
  std::span<const Index> of(Index i) const {
    return {indices.data() + offsets[static_cast<std::size_t>(i)], static_cast<std::size_t>(count(i))};
  }
  std::span<const Real> distances_of(Index i) const {
    return {distances.data() + offsets[static_cast<std::size_t>(i)], static_cast<std::size_t>(count(i))};
  }
  Real radius(Index i) const { return radii[static_cast<std::size_t>(i)]; }
};

}  // namespace vrsph
