// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <random>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/brute_force.hpp>
#include <vrsph/neighbours/search.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud random_cloud(int dim, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  PointCloud c;
  c.dim = dim;
  for (int i = 0; i < n; ++i) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < dim; ++k) x[k] = u(rng) * (k == 0 ? 2.0 : 1.0);  // anisotropic bounding box
    c.add(x, Tag::Interior);
  }
  return c;
}
}  // namespace

class SearchVsBruteForce : public ::testing::TestWithParam<std::tuple<int, SearchBackend, bool>> {};

TEST_P(SearchVsBruteForce, AgreesExactlyAsSets) {
  const auto [dim, backend, variable] = GetParam();
  const PointCloud c = random_cloud(dim, dim == 1 ? 400 : 1500, 7u + static_cast<unsigned>(dim));
  SearchParams p;
  p.backend = backend;
  p.min_neighbours = 0;
  p.radius = dim == 1 ? 0.02 : dim == 2 ? 0.08 : 0.2;
  if (variable) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.5, 2.0);
    for (Index i = 0; i < c.size(); ++i) p.radii.push_back(p.radius * u(rng));
  }
  const NeighbourList fast = find_neighbours(c, p), ref = find_neighbours_brute_force(c, p);
  ASSERT_EQ(fast.offsets, ref.offsets);
  ASSERT_EQ(fast.indices, ref.indices);
  ASSERT_EQ(fast.distances.size(), fast.indices.size());
  for (Index i = 0; i < c.size(); ++i)
    for (Index k = fast.offsets[static_cast<std::size_t>(i)]; k < fast.offsets[static_cast<std::size_t>(i) + 1]; ++k) {
      const Index j = fast.indices[static_cast<std::size_t>(k)];
      EXPECT_NE(i, j);
      EXPECT_DOUBLE_EQ(fast.distances[static_cast<std::size_t>(k)], (c.positions[static_cast<std::size_t>(i)] - c.positions[static_cast<std::size_t>(j)]).norm());
      EXPECT_LT(fast.distances[static_cast<std::size_t>(k)], fast.radius(i));
    }
  EXPECT_GT(fast.total(), 0);
}

INSTANTIATE_TEST_SUITE_P(Backends, SearchVsBruteForce,
                         ::testing::Combine(::testing::Values(1, 2, 3),
                                            ::testing::Values(SearchBackend::CellList, SearchBackend::KdTree),
                                            ::testing::Bool()));

// Rows sorted by index whatever order their candidates arrive in: a cloud numbered along its
// lattice (nearly sorted runs: the cell list's insertion sort alone) and the same cloud numbered
// at random (rows long enough that the sort gives up on insertion), wide radii in 2D and 3D.
TEST(Search, RowsInIndexOrderOnLatticeAndShuffledNumberings) {
  for (const int dim : {2, 3}) {
    const int n = dim == 2 ? 40 : 12;
    std::mt19937 rng(5u + static_cast<unsigned>(dim));
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    PointCloud lattice;
    lattice.dim = dim;
    for (int c = 0; c < (dim == 3 ? n : 1); ++c)
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          Vec3 x(a + jitter(rng), b + jitter(rng), dim == 3 ? c + jitter(rng) : 0.0);
          lattice.add(x / n, Tag::Interior);
        }
    std::vector<Index> perm(static_cast<std::size_t>(lattice.size()));
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<Index>(i);
    std::shuffle(perm.begin(), perm.end(), rng);
    PointCloud shuffled;
    shuffled.dim = dim;
    for (const Index i : perm) shuffled.add(lattice.positions[static_cast<std::size_t>(i)], Tag::Interior);
    SearchParams p;
    p.min_neighbours = 0;
    p.radius = (dim == 2 ? 6.0 : 4.0) / n;  // rows of about 110 (2D) and 270 (3D)
    for (const PointCloud* c : {&lattice, &shuffled}) {
      const NeighbourList fast = find_neighbours(*c, p), ref = find_neighbours_brute_force(*c, p);
      ASSERT_EQ(fast.offsets, ref.offsets) << dim << "D";
      ASSERT_EQ(fast.indices, ref.indices) << dim << "D";
      EXPECT_GT(fast.total(), (dim == 2 ? 90 : 200) * c->size() / 2);
    }
  }
}

// A search written into another list's arrays (what a Verlet list does at every search of a
// moving cloud) equals the plain search, whatever that list held: more pairs or fewer, cached
// distances or none, periodic shifts.
TEST(Search, IntoReusedStorageEqualsAPlainSearch) {
  for (const SearchBackend backend : {SearchBackend::CellList, SearchBackend::KdTree}) {
    const PointCloud c = random_cloud(2, 1500, 11u);
    SearchParams p;
    p.backend = backend;
    p.min_neighbours = 0;
    p.radius = 0.08;
    const NeighbourList plain = find_neighbours(c, p);
    SearchParams without_distances = p;
    without_distances.cache_distances = false;
    for (const Real other_radius : {0.04, 0.08, 0.16}) {
      SearchParams q = p;
      q.radius = other_radius;
      NeighbourList storage = find_neighbours(c, q);
      storage.shifts.assign(storage.indices.size(), 4);  // as a periodic list has
      const Index* before = storage.indices.data();
      const bool fits = storage.indices.capacity() >= plain.indices.size();
      const NeighbourList reused = find_neighbours(c, p, std::move(storage));
      EXPECT_EQ(reused.offsets, plain.offsets);
      EXPECT_TRUE(reused.indices == plain.indices);
      EXPECT_TRUE(reused.distances == plain.distances);  // bit for bit
      EXPECT_TRUE(reused.shifts.empty());
      EXPECT_EQ(reused.radii, plain.radii);
      if (fits) {
        EXPECT_EQ(reused.indices.data(), before) << "storage with room enough was re-allocated";
      }
      const NeighbourList bare = find_neighbours(c, without_distances, find_neighbours(c, q));
      EXPECT_TRUE(bare.indices == plain.indices);
      EXPECT_TRUE(bare.distances.empty());
    }
  }
}

TEST(Search, PeriodicIntoReusedStorageEqualsAPlainSearch) {
  PointCloud c = random_cloud(2, 1500, 13u);
  c.domain = Domain::unit_box(2);
  c.domain.hi[0] = 2;  // random_cloud's box is [0, 2] x [0, 1]
  c.domain.set_periodic("x,y");
  SearchParams p;
  p.min_neighbours = 0;
  p.radius = 0.08;
  const NeighbourList plain = find_neighbours(c, p);
  ASSERT_FALSE(plain.shifts.empty());
  SearchParams flat = p;
  flat.wrap_periodic = false;
  flat.radius = 0.12;
  const NeighbourList reused = find_neighbours(c, p, find_neighbours(c, flat));
  EXPECT_EQ(reused.offsets, plain.offsets);
  EXPECT_TRUE(reused.indices == plain.indices);
  EXPECT_TRUE(reused.distances == plain.distances);
  EXPECT_EQ(reused.shifts, plain.shifts);
}

TEST(Search, StrictRadiusAndSelf) {
  // Lattice spacing 1: with radius exactly 1 the face neighbours (r = 1) are excluded.
  PointCloud c = vertex_lattice(Domain::box(2, Vec3(0, 0, 0), Vec3(4, 4, 0)), 4);
  SearchParams p;
  p.radius = 1.0;
  p.min_neighbours = 0;
  EXPECT_EQ(find_neighbours(c, p).total(), 0);
  p.radius = 1.0 + 1e-9;
  p.include_self = true;
  const auto nl = find_neighbours(c, p);
  EXPECT_EQ(nl.count(12), 5);  // centre particle: itself + 4 face neighbours
}

// The cell list scans, per row of cells, only the run its ball can touch, trusting a gap to a
// row of cells only beyond rounding. Lattices whose points lie on the cells' faces and whose
// pairs sit at the radius to rounding, and clouds far from the origin (where rounding is
// largest against the radius), must still give exactly the brute-force sets.
TEST(Search, CellListStripsMissNoPairOnCellFacesOrFarFromTheOrigin) {
  for (const int dim : {1, 2, 3}) {
    for (const Real offset : {0.0, 1e6, -3.7e8}) {
      for (const Real radius : {0.2, 0.2 * (1 + 1e-15), 0.1 * std::sqrt(2.0), 0.1 * std::sqrt(5.0), 0.35}) {
        PointCloud c = vertex_lattice(Domain::unit_box(dim), dim == 3 ? 8 : 10);
        for (Vec3& x : c.positions)
          for (int k = 0; k < dim; ++k) x[k] += offset;
        SearchParams p;
        p.min_neighbours = 0;
        p.radius = radius;
        const NeighbourList fast = find_neighbours(c, p), ref = find_neighbours_brute_force(c, p);
        ASSERT_EQ(fast.offsets, ref.offsets) << dim << "D, offset " << offset << ", radius " << radius;
        ASSERT_EQ(fast.indices, ref.indices);
        ASSERT_TRUE(fast.distances == ref.distances);
      }
    }
    // Random points far from the origin with radii spread over a factor 8.
    PointCloud c = random_cloud(dim, dim == 1 ? 300 : 1200, 31u + static_cast<unsigned>(dim));
    for (Vec3& x : c.positions)
      for (int k = 0; k < dim; ++k) x[k] = 2.5e7 + x[k];
    SearchParams p;
    p.min_neighbours = 0;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.25, 2.0);
    const Real base = dim == 1 ? 0.02 : dim == 2 ? 0.06 : 0.25;  // 3D: about 5 particles a half-radius cell (that grid)
    for (Index i = 0; i < c.size(); ++i) p.radii.push_back(base * u(rng));
    const NeighbourList fast = find_neighbours(c, p), ref = find_neighbours_brute_force(c, p);
    ASSERT_EQ(fast.offsets, ref.offsets) << dim << "D random";
    ASSERT_EQ(fast.indices, ref.indices);
    ASSERT_TRUE(fast.distances == ref.distances);
  }
}

TEST(Search, DuplicatesAreReportedByIndex) {
  PointCloud c = random_cloud(2, 50, 1);
  c.add(c.positions[17], Tag::Interior);
  SearchParams p;
  p.radius = 0.3;
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "duplicate particles 17 and 50");
  p.backend = SearchBackend::KdTree;
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "duplicate particles 17 and 50");
  // The message states the tolerance and the radius it scales with: a radius inflated by an
  // outlier (a spacing estimated from a stray particle) shows there.
  p.backend = SearchBackend::CellList;
  p.radius = 2e9;
  c = random_cloud(2, 50, 1);
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "is below the duplicate tolerance 0.2 (1e-10 times the support radius 2000000000)");
}

TEST(Search, TooFewNeighboursIsAGeometryError) {
  PointCloud c = random_cloud(2, 20, 2);
  c.add(Vec3(10, 10, 0), Tag::Interior);
  SearchParams p;
  p.radius = 0.9;
  EXPECT_THROW_MSG(find_neighbours(c, p), GeometryError, "particle 20 at (10, 10, 0) has 0 neighbours");
  c.tags.back() = Tag::Ghost;  // ghosts may be isolated
  EXPECT_NO_THROW(find_neighbours(c, p));
}

TEST(Search, RejectsBadRadiiAndCoordinates) {
  PointCloud c = random_cloud(3, 10, 3);
  SearchParams p;
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "search radius must be positive");
  p.radius = 1;
  p.radii = {1.0, 2.0};
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "got 2 values for 10 particles");
  p.radii.clear();
  c.positions[4][1] = std::nan("");
  EXPECT_THROW_MSG(find_neighbours(c, p), InputError, "particle 4 has a non-finite coordinate y");
}

TEST(Search, KnnQueries) {
  const PointCloud c = vertex_lattice(Domain::unit_box(2), 10);
  const auto d1 = kth_neighbour_distance(c, 1);
  for (double d : d1) EXPECT_NEAR(d, 0.1, 1e-12);
  const auto d5 = kth_neighbour_distance(c, 5);  // centre-ish: 4 at 0.1, then sqrt(2)*0.1
  EXPECT_NEAR(d5[60], std::sqrt(2.0) * 0.1, 1e-12);
  const auto cp = closest_pair(c);
  EXPECT_NEAR(cp.distance, 0.1, 1e-12);
  EXPECT_NEAR(mean_nearest_neighbour_distance(c), 0.1, 1e-12);
}

TEST(Search, DistanceToTaggedBoundaryMatchesTheDomainOnALattice) {
  // On a vertex lattice the nearest face point of an interior particle is a boundary
  // particle, so the two distances agree; a cloud without boundary particles gives infinity.
  const PointCloud c = vertex_lattice(Domain::unit_box(2), 10);
  const std::vector<Real> d = distance_to_tagged_boundary(c);
  ASSERT_EQ(static_cast<Index>(d.size()), c.size());
  for (Index i = 0; i < c.size(); ++i)
    EXPECT_NEAR(d[static_cast<std::size_t>(i)], c.domain.signed_distance(c.positions[static_cast<std::size_t>(i)]), 1e-12);
  PointCloud inner;
  inner.dim = 2;
  inner.add(Vec3(0, 0, 0), Tag::Interior);
  EXPECT_TRUE(std::isinf(distance_to_tagged_boundary(inner)[0]));
}
