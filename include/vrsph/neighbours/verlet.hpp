// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Neighbour lists of particles that move, kept with a Verlet skin. A search finds the
// candidates within radius + skin; while no two particles together have moved more than the
// skin since that search (d1 + d2 <= skin for the two largest displacements: no pair's
// distance can have changed by more), every pair now within the radius is among the
// candidates, and an update only re-filters them at the current positions. Otherwise it
// searches again. Either way the list equals find_neighbours on the same positions entry for
// entry, distances and periodic shifts bit for bit (the same expressions), with the same
// checks (duplicates, too few neighbours, a periodic particle outside its box); its storage is
// reused from step to step.
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

class VerletNeighbours {
 public:
  /// `params` as for find_neighbours (cache_distances is forced on: every method reads
  /// distances); `skin` >= 0 in the units of the positions. On a periodic box the skin is
  /// capped so that radius + skin stays below half of every period (one image per candidate).
  VerletNeighbours(SearchParams params, Real skin);

  /// The list at the cloud's current positions. InputError for a cloud of another size or
  /// dimension than the first one, non-finite positions, duplicates, or (periodic) a particle
  /// outside [lo, hi); GeometryError for too few neighbours. When it throws, list() is the
  /// last list still.
  const NeighbourList& update(const PointCloud& cloud);
  const NeighbourList& list() const { return list_; }
  /// Per-particle support radii for the next update (one per particle of the cloud the list was
  /// built for; positive and finite, on a periodic box below half of every period less the skin).
  /// A radius above the one its row was last searched with makes the next update search again;
  /// smaller ones only re-filter. InputError otherwise, the radii unchanged.
  void set_radii(std::vector<Real> radii);
  const std::vector<Real>& radii() const { return list_.radii; }

  Real skin() const { return skin_; }
  Index searches() const { return searches_; }     ///< updates that searched
  Index refilters() const { return refilters_; }   ///< updates that re-filtered the candidates
  bool last_searched() const { return last_searched_; }
  Index candidates() const { return candidates_.total(); }

 private:
  void search(const PointCloud& cloud);
  bool moved_too_far(const PointCloud& cloud) const;
  void refilter(const PointCloud& cloud);

  SearchParams params_;
  Real skin_ = 0;
  int dim_ = 0;
  Index size_ = -1;
  NeighbourList candidates_;           ///< pairs within radius + skin at the last search
  std::vector<Vec3> searched_at_;      ///< positions at the last search
  std::vector<Real> searched_radii_;   ///< the rows' radii at the last search
  bool radii_grew_ = false;            ///< the radii set exceed those of the last search somewhere
  Real period_limit_ = 0;              ///< on a periodic box: radius + skin must stay below this (0: none)
  NeighbourList list_;
  UninitVector<Index> scratch_index_;  ///< per candidate slot: the kept pairs of each row, packed at its start
  UninitVector<Real> scratch_distance_;
  std::vector<std::uint8_t> scratch_shift_;
  std::vector<Index> kept_;          ///< per row: its pairs within the radius
  NeighbourList next_;               ///< the next row pointers, checked before they are the list's
  Index searches_ = 0, refilters_ = 0;
  bool last_searched_ = false;
};

}  // namespace vrsph
