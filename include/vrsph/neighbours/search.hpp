// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Radius neighbour search, built in two passes (count, then fill) so the CSR
// arrays are sized once and never reallocated.
//
// How to choose the backend: CellList (default) bins particles into cells of half the
// largest search radius (whole where half cells would hold few particles, or be many more than
// the particles) and scans
// per row of cells only the run each particle's ball can touch; expected O(N) for quasi-uniform
// clouds and the faster of
// the two in `vrsph bench neighbours` on every cloud we ship. KdTree (nanoflann)
// is the robust choice for strongly graded clouds or radii that vary by orders of
// magnitude, where a uniform cell size wastes work.
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>

namespace vrsph {

enum class SearchBackend { CellList, KdTree };

struct SearchParams {
  Real radius = 0;            ///< support radius used for every particle if `radii` is empty
  std::vector<Real> radii;    ///< optional per-particle radius (gather: j in N_i iff r_ij < radii[i])
  bool include_self = false;  ///< list i in its own row
  bool cache_distances = true;
  SearchBackend backend = SearchBackend::CellList;
  /// Rows of non-ghost particles with fewer neighbours than this raise GeometryError.
  Index min_neighbours = 1;
  /// Two particles closer than duplicate_tolerance * radius are reported as duplicates (InputError).
  Real duplicate_tolerance = 1e-10;
  /// A cloud whose box is periodic (Domain::periodic) is searched with minimum-image
  /// distances, each pair's image in NeighbourList::shifts. False: search the positions as
  /// they are (a cloud that already holds its periodic images).
  bool wrap_periodic = true;
};

/// Throws InputError (non-positive or non-finite radius, duplicate particles; on a periodic
/// box a period not larger than twice the radius or a particle outside the box) or
/// GeometryError (a non-ghost particle with too few neighbours), naming the particle.
NeighbourList find_neighbours(const PointCloud& cloud, const SearchParams& params);
/// The same search written into `storage`'s arrays (their capacity reused, their contents
/// replaced): a moving cloud searched again and again pages in no fresh memory. The list is
/// equal to the one-argument form's. (On a periodic box the search over the images is a
/// temporary of its own; the list it leaves is written into `storage`.)
NeighbourList find_neighbours(const PointCloud& cloud, const SearchParams& params, NeighbourList storage);

/// For each query point (any point, a particle or not), the particles strictly closer than
/// `radius`, in increasing index (k-d tree). InputError for a non-positive radius or a
/// non-finite query point.
std::vector<std::vector<Index>> particles_within(const PointCloud& cloud, const std::vector<Vec3>& queries, Real radius);
/// Mean distance to the nearest other particle (used when no spacing is known).
Real mean_nearest_neighbour_distance(const PointCloud& cloud);

/// Minimum pairwise distance and the pair attaining it (i < j); {inf,-1,-1} for N < 2.
struct ClosestPair {
  Real distance;
  Index i, j;
};
ClosestPair closest_pair(const PointCloud& cloud);

/// Distance from each particle to its k-th nearest other particle (k >= 1), e.g. for a
/// per-particle smoothing radius h_i = factor * dist_k.
std::vector<Real> kth_neighbour_distance(const PointCloud& cloud, int k);
/// Per particle, the distance to the nearest tagged boundary particle (Dirichlet or
/// Neumann; 0 for those themselves), infinity if the cloud has none: "near the boundary"
/// for clouds without a known domain (users' files).
std::vector<Real> distance_to_tagged_boundary(const PointCloud& cloud);
/// Per query, the distance to the nearest of `points` (of dimension dim), infinity if there
/// are none: e.g. to boundary particles gathered from every MPI rank.
std::vector<Real> distance_to_points(const std::vector<Vec3>& points, int dim, const std::vector<Vec3>& queries);

}  // namespace vrsph
