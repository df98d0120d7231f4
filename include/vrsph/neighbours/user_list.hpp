// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A neighbour list the caller already has (its own search, a list kept between time steps),
// checked and completed into the NeighbourList every method reads: rows sorted, distances
// computed where not given, the support radius of every row recorded.
#include <span>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>

namespace vrsph {

struct UserNeighbours {
  std::span<const Index> offsets;   ///< N + 1 row pointers (CSR), offsets[0] = 0
  std::span<const Index> indices;   ///< offsets[N] entries: the neighbours of each row, any order, no self
  std::span<const Real> distances;  ///< empty (computed from the positions), or one |x_j - x_i| per entry
  std::span<const Real> radii;      ///< the support radius: one for every particle, or one per particle
  /// Candidate pairs (a Verlet list, a cell list's pairs): entries at or beyond the row's support
  /// radius are dropped instead of refused, the others checked as a list's.
  bool candidates = false;
  Index min_neighbours = 1;  ///< fewer in a non-ghost particle's row: GeometryError (0: a particle may stand alone)
};

/// Checks the list against the cloud and returns it in the library's form. InputError, naming
/// the first offending particle, for: offsets of the wrong size, not starting at 0, decreasing
/// or not ending at the number of entries; an index out of range, the row's own particle or
/// listed twice in a row; a neighbour at or beyond the row's support radius; a given distance
/// that the positions contradict (beyond 1e-9 of the radius); a pair within both particles'
/// radii listed in one row only (a broken symmetric list); a radius that is not positive and
/// finite; two particles closer than the search's duplicate tolerance (1e-10 of the support
/// radius). GeometryError, as the search raises it, for a non-ghost particle without neighbours.
/// Not checked: pairs missing from both rows (that needs a search of its own). With
/// `candidates`, entries beyond the radius are dropped and the particle without neighbours is
/// found among the rows that remain.
/// On a periodic box (Domain::periodic) a pair is taken across the periodic faces to the
/// nearest image, whose shift code is stored as the minimum-image search stores it; the box is
/// checked as that search checks it (period above twice the largest radius, particles inside).
NeighbourList neighbour_list_from(const PointCloud& cloud, const UserNeighbours& user);

}  // namespace vrsph
