// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Covering radius r_N = max over x in the domain of min_i |x - x_i| ([IM](5), [QW] §4;
// METHODS §3.8.4), computed exactly for box and ball domains in 1D, 2D and 3D.
//
// Method: on each Voronoi cell clipped to the domain the distance to the cell's particle
// is convex, so its maximum lies at a vertex of the clipped cell, or (on a ball's sphere)
// at the point of an arc farthest from the particle. Candidates are generated from the
// CGAL Delaunay triangulation: Voronoi vertices (circumcentres), Voronoi edges/facets
// (duals of Delaunay facets/edges) intersected with the box faces/edges or the sphere,
// box corners, and antipodal sphere points. Each candidate inside the domain is scored
// with its true nearest-particle distance (k-d tree), so a superset of candidates can
// never overestimate. All particles (ghosts included) count as covering points.
#include <functional>
#include <span>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct CoveringRadius {
  Real radius = 0;
  Vec3 point = Vec3::Zero();  ///< where the maximum is attained
  Index nearest = -1;         ///< the particle nearest to that point
  Index candidates = 0;       ///< candidate points scored
  Real uncertainty = 0;       ///< the true r_N lies in [radius, radius + uncertainty] (0: exact)
};

/// Throws InputError for a cloud without a box or ball domain, or with fewer than d+1 particles.
/// A box periodic along some axes: the largest empty ball of the periodic point set (every
/// particle inside the box along those axes, else InputError; `point` in the box, `nearest` an
/// original), ConfigError when it reaches half a period.
CoveringRadius covering_radius(const PointCloud& cloud);

/// One rank's share of the covering radius of a distributed cloud: the largest distance
/// from a candidate point (as above, of the `local` cloud: owned and halo particles) to
/// its nearest particle, over the candidates nearest to an `owned` particle. Exactness:
/// the local Voronoi cell of an owned particle contains its cell in the whole cloud, so
/// the maximum over ranks is >= r_N; a candidate at distance d from its nearest owned
/// particle is scored exactly when every particle within 2d of that one is local. Hence,
/// with a halo of every particle within w of the owned ones, the maximum over ranks is
/// r_N exactly when it is <= w / 2 (else: widen the halo and call again). `spacing` sets
/// the round-off tolerance of the domain test (as the whole cloud's spacing would).
/// `nearest` is a local index; a rank without owned particles gives radius 0.
CoveringRadius covering_radius_of_owned(const PointCloud& local, std::span<const char> owned, Real spacing);

/// The covering radius over a general domain (a polygon, a solid bounded by a surface), given
/// by a membership test and a sample of its boundary in which every boundary point has a
/// sample point within `boundary_step`. Interior maxima of the nearest-particle distance are
/// Voronoi vertices, which are all scored, so the interior is exact; on the boundary the
/// distance (1-Lipschitz) is at most boundary_step above its sampled maximum. Hence
/// radius <= r_N <= radius + boundary_step, reported as `uncertainty`. 2D and 3D clouds.
CoveringRadius covering_radius(const PointCloud& cloud, const std::function<bool(const Vec3&)>& inside,
                               const std::vector<Vec3>& boundary_sample, Real boundary_step);

namespace detail {
/// Candidate points (see above) for 2D/3D clouds; implemented with CGAL.
std::vector<Vec3> covering_candidates(const PointCloud& cloud);
}  // namespace detail

}  // namespace vrsph
