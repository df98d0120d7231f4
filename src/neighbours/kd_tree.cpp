// SPDX-License-Identifier: BSD-3-Clause
// nanoflann k-d tree backend, plus the k-nearest-neighbour queries (spacing,
// closest pair, k-th neighbour distance) that only a tree answers well.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
// GCC 12 reports a false -Wnull-dereference inside nanoflann's index construction
// (std::vector<uint32_t>::resize inlined into our code); nothing of ours is involved.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <nanoflann.hpp>
#include "nearest_particles.hpp"
#include "two_pass.hpp"

namespace vrsph::detail {

namespace {
struct CloudAdaptor {
  const PointCloud& cloud;
  std::size_t kdtree_get_point_count() const { return cloud.positions.size(); }
  Real kdtree_get_pt(std::size_t idx, std::size_t k) const { return cloud.positions[idx][static_cast<Eigen::Index>(k)]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

template <int D>
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, CloudAdaptor>, CloudAdaptor, D,
                                                 std::uint32_t>;

// Forwards every point the tree reports inside the (squared) search radius.
template <class Emit>
struct CallbackResultSet {
  using DistanceType = Real;
  using IndexType = std::uint32_t;
  Real r2max;
  Emit& emit;
  std::size_t found = 0;
  void init() {}
  std::size_t size() const { return found; }
  bool full() const { return true; }
  bool addPoint(Real r2, std::uint32_t j) {
    ++found;
    emit(static_cast<Index>(j), r2);
    return true;
  }
  Real worstDist() const { return r2max; }
};

template <int D>
NeighbourList search_dim(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                         NeighbourList storage) {
  CloudAdaptor adaptor{cloud};
  Tree<D> tree(D, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  auto visit = [&](Index i, Real r, auto&& emit) {
    // Slightly enlarge the tree's bound; the driver applies the strict r < radius test.
    CallbackResultSet<std::remove_reference_t<decltype(emit)>> rs{r * r * (1 + 1e-12), emit};
    tree.findNeighbors(rs, cloud.positions[static_cast<std::size_t>(i)].data(), nanoflann::SearchParams(32, 0, false));
  };
  return two_pass_search(cloud, std::move(radii), params, visit, std::move(storage));
}

// Index and squared distance of the k nearest other particles of every particle.
template <int D>
void knn_dim(const PointCloud& cloud, int k, std::vector<Real>& dist_k, std::vector<Index>* nearest) {
  CloudAdaptor adaptor{cloud};
  Tree<D> tree(D, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const Index n = cloud.size();
  dist_k.assign(static_cast<std::size_t>(n), std::numeric_limits<Real>::infinity());
  if (nearest) nearest->assign(static_cast<std::size_t>(n), -1);
  const auto want = static_cast<std::size_t>(k) + 1;  // the particle itself comes back too
#pragma omp parallel
  {
    std::vector<std::uint32_t> idx(want);
    std::vector<Real> d2(want);
#pragma omp for
    for (Index i = 0; i < n; ++i) {
      nanoflann::KNNResultSet<Real, std::uint32_t> rs(want);
      rs.init(idx.data(), d2.data());
      tree.findNeighbors(rs, cloud.positions[static_cast<std::size_t>(i)].data(), nanoflann::SearchParams());
      // Skip the query particle itself (exactly one zero-distance hit with index i).
      int seen = 0;
      for (std::size_t m = 0; m < rs.size(); ++m) {
        if (idx[m] == static_cast<std::uint32_t>(i)) continue;
        if (++seen == k) {
          dist_k[static_cast<std::size_t>(i)] = std::sqrt(d2[m]);
          if (nearest) (*nearest)[static_cast<std::size_t>(i)] = static_cast<Index>(idx[m]);
          break;
        }
      }
    }
  }
}

void knn(const PointCloud& cloud, int k, std::vector<Real>& dist_k, std::vector<Index>* nearest) {
  switch (cloud.dim) {
    case 1: return knn_dim<1>(cloud, k, dist_k, nearest);
    case 2: return knn_dim<2>(cloud, k, dist_k, nearest);
    default: return knn_dim<3>(cloud, k, dist_k, nearest);
  }
}
}  // namespace

namespace {
template <int D>
void nearest_dim(const PointCloud& cloud, const std::vector<Vec3>& queries, std::vector<Real>& dist,
                 std::vector<Index>& index) {
  CloudAdaptor adaptor{cloud};
  Tree<D> tree(D, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  dist.assign(queries.size(), 0);
  index.assign(queries.size(), -1);
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < queries.size(); ++q) {
    std::uint32_t i = 0;
    Real d2 = 0;
    nanoflann::KNNResultSet<Real, std::uint32_t> rs(1);
    rs.init(&i, &d2);
    tree.findNeighbors(rs, queries[q].data(), nanoflann::SearchParams());
    dist[q] = std::sqrt(d2);
    index[q] = static_cast<Index>(i);
  }
}
}  // namespace

template <int D>
std::vector<std::vector<Index>> within_dim(const PointCloud& cloud, const std::vector<Vec3>& queries, Real radius) {
  CloudAdaptor adaptor{cloud};
  Tree<D> tree(D, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  std::vector<std::vector<Index>> out(queries.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t q = 0; q < queries.size(); ++q) {
    auto emit = [&](Index j, Real r2) {
      if (r2 < radius * radius) out[q].push_back(j);  // the strict r < radius of every search
    };
    CallbackResultSet<decltype(emit)> rs{radius * radius * (1 + 1e-12), emit};
    tree.findNeighbors(rs, queries[q].data(), nanoflann::SearchParams(32, 0, false));
    std::sort(out[q].begin(), out[q].end());
  }
  return out;
}

void nearest_particles(const PointCloud& cloud, const std::vector<Vec3>& queries, std::vector<Real>& dist,
                       std::vector<Index>& index) {
  switch (cloud.dim) {
    case 1: return nearest_dim<1>(cloud, queries, dist, index);
    case 2: return nearest_dim<2>(cloud, queries, dist, index);
    default: return nearest_dim<3>(cloud, queries, dist, index);
  }
}

std::vector<std::vector<Index>> particles_within_dim(const PointCloud& cloud, const std::vector<Vec3>& queries,
                                                     Real radius) {
  switch (cloud.dim) {
    case 1: return within_dim<1>(cloud, queries, radius);
    case 2: return within_dim<2>(cloud, queries, radius);
    default: return within_dim<3>(cloud, queries, radius);
  }
}

NeighbourList kd_tree_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                             NeighbourList storage) {
  switch (cloud.dim) {
    case 1: return search_dim<1>(cloud, std::move(radii), params, std::move(storage));
    case 2: return search_dim<2>(cloud, std::move(radii), params, std::move(storage));
    default: return search_dim<3>(cloud, std::move(radii), params, std::move(storage));
  }
}

}  // namespace vrsph::detail

namespace vrsph {

std::vector<std::vector<Index>> particles_within(const PointCloud& cloud, const std::vector<Vec3>& queries, Real radius) {
  validate(cloud);
  check<InputError>(std::isfinite(radius) && radius > 0, "a query radius must be positive and finite, got ", radius);
  for (std::size_t q = 0; q < queries.size(); ++q)
    for (int k = 0; k < 3; ++k)
      check<InputError>(std::isfinite(queries[q][k]) && std::abs(queries[q][k]) <= max_coordinate, "query point ", q,
                        " has coordinate ", queries[q][k]);
  return detail::particles_within_dim(cloud, queries, radius);
}

std::vector<Real> kth_neighbour_distance(const PointCloud& cloud, int k) {
  validate(cloud);
  check<InputError>(k >= 1, "k-th neighbour distance needs k >= 1, got ", k);
  check<GeometryError>(cloud.size() > k, "k-th neighbour distance with k = ", k, " needs more than ", k,
                       " particles, the cloud has ", cloud.size());
  std::vector<Real> d;
  detail::knn(cloud, k, d, nullptr);
  return d;
}

std::vector<Real> distance_to_points(const std::vector<Vec3>& points, int dim, const std::vector<Vec3>& queries) {
  if (points.empty()) return std::vector<Real>(queries.size(), std::numeric_limits<Real>::infinity());
  PointCloud wall;
  wall.dim = dim;
  wall.positions = points;
  wall.tags.assign(points.size(), Tag::Dirichlet);
  std::vector<Real> d;
  std::vector<Index> nearest;
  detail::nearest_particles(wall, queries, d, nearest);
  return d;
}

std::vector<Real> distance_to_tagged_boundary(const PointCloud& cloud) {
  std::vector<Vec3> wall;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Tag t = cloud.tags[static_cast<std::size_t>(i)];
    if (t == Tag::Dirichlet || t == Tag::Neumann) wall.push_back(cloud.positions[static_cast<std::size_t>(i)]);
  }
  return distance_to_points(wall, cloud.dim, cloud.positions);
}

Real mean_nearest_neighbour_distance(const PointCloud& cloud) {
  if (cloud.size() < 2) return 0;
  const auto d = kth_neighbour_distance(cloud, 1);
  Real s = 0;
  for (Real v : d) s += v;
  return s / static_cast<Real>(d.size());
}

ClosestPair closest_pair(const PointCloud& cloud) {
  ClosestPair best{std::numeric_limits<Real>::infinity(), -1, -1};
  if (cloud.size() < 2) return best;
  validate(cloud);
  std::vector<Real> d;
  std::vector<Index> nearest;
  detail::knn(cloud, 1, d, &nearest);
  for (Index i = 0; i < cloud.size(); ++i) {
    const Real di = d[static_cast<std::size_t>(i)];
    if (di < best.distance) best = {di, std::min(i, nearest[static_cast<std::size_t>(i)]), std::max(i, nearest[static_cast<std::size_t>(i)])};
  }
  return best;
}

}  // namespace vrsph

#pragma GCC diagnostic pop
