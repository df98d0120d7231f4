// SPDX-License-Identifier: BSD-3-Clause
// Periodic boxes: the minimum-image search against a brute force over the 27 images, the
// shifts stored with the pairs, the lattices without boundary particles on periodic axes,
// and the refusals (a period not larger than 2 h, a particle outside the box).
#include <random>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud random_periodic_cloud(int dim, int n, const std::string& axes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  PointCloud c;
  c.dim = dim;
  c.domain = Domain::box(dim, Vec3::Zero(), Vec3(2.0, 1.0, 1.0));
  c.domain.set_periodic(axes);
  for (int i = 0; i < n; ++i) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < dim; ++k) x[k] = u(rng) * (k == 0 ? 2.0 : 1.0);
    c.add(x, Tag::Interior);
  }
  return c;
}

// Every pair within r under the minimum image, with the shift that realises it.
std::vector<std::vector<std::pair<Index, std::uint8_t>>> brute_force(const PointCloud& c, Real r) {
  std::vector<std::vector<std::pair<Index, std::uint8_t>>> rows(static_cast<std::size_t>(c.size()));
  for (Index i = 0; i < c.size(); ++i)
    for (Index j = 0; j < c.size(); ++j)
      for (std::uint8_t code = 0; code < 27; ++code) {
        bool allowed = true;
        for (int k = 0; k < 3; ++k) {
          const int s = code / (k == 0 ? 1 : k == 1 ? 3 : 9) % 3 - 1;
          if (s != 0 && (k >= c.dim || !c.domain.periodic[static_cast<std::size_t>(k)])) allowed = false;
        }
        if (!allowed || (i == j && code == no_shift)) continue;
        const Vec3 d = c.positions[static_cast<std::size_t>(j)] + periodic_shift(c.domain, code) - c.positions[static_cast<std::size_t>(i)];
        if (d.norm() < r) rows[static_cast<std::size_t>(i)].emplace_back(j, code);
      }
  return rows;
}
}  // namespace

class PeriodicSearch : public ::testing::TestWithParam<std::tuple<int, std::string, SearchBackend>> {};

TEST_P(PeriodicSearch, MinimumImagePairsAndShiftsAsBruteForce) {
  const auto [dim, axes, backend] = GetParam();
  const PointCloud c = random_periodic_cloud(dim, dim == 1 ? 200 : dim == 2 ? 600 : 900, axes, 11u);
  const Real r = dim == 1 ? 0.05 : dim == 2 ? 0.12 : 0.2;
  SearchParams sp;
  sp.radius = r;
  sp.backend = backend;
  sp.min_neighbours = 0;
  const NeighbourList nl = find_neighbours(c, sp);
  const auto ref = brute_force(c, r);
  ASSERT_EQ(nl.shifts.size(), static_cast<std::size_t>(nl.total()));
  Index across = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const auto row = nl.of(i);
    const auto& want = ref[static_cast<std::size_t>(i)];
    ASSERT_EQ(row.size(), want.size()) << "particle " << i;
    for (std::size_t k = 0; k < row.size(); ++k) {
      const auto e = static_cast<std::size_t>(nl.offsets[static_cast<std::size_t>(i)]) + k;
      EXPECT_EQ(row[k], want[k].first) << "particle " << i;  // sorted by index, as a plain search
      EXPECT_EQ(nl.shifts[e], want[k].second) << "particle " << i;
      const Vec3 d = c.positions[static_cast<std::size_t>(row[k])] + periodic_shift(c.domain, nl.shifts[e]) -
                     c.positions[static_cast<std::size_t>(i)];
      EXPECT_NEAR(nl.distances[e], d.norm(), 1e-14);
      across += nl.shifts[e] != no_shift;
    }
  }
  EXPECT_GT(across, 0);  // the test saw pairs across the faces
}

INSTANTIATE_TEST_SUITE_P(Axes, PeriodicSearch,
                         ::testing::Values(std::make_tuple(1, std::string("x"), SearchBackend::CellList),
                                           std::make_tuple(2, std::string("x,y"), SearchBackend::CellList),
                                           std::make_tuple(2, std::string("x"), SearchBackend::KdTree),
                                           std::make_tuple(2, std::string("y"), SearchBackend::CellList),
                                           std::make_tuple(3, std::string("all"), SearchBackend::CellList),
                                           std::make_tuple(3, std::string("x,z"), SearchBackend::KdTree)));

// knn support radii on a periodic box: the k-th minimum-image distance, as the brute force over
// the images finds it; a particle near a face counts its neighbours across it.
TEST(PeriodicKnn, KthDistanceIsTheMinimumImageOne) {
  for (const auto& [dim, axes] : {std::pair{1, "x"}, std::pair{2, "x,y"}, std::pair{2, "y"}, std::pair{3, "x,z"}}) {
    const PointCloud c = random_periodic_cloud(dim, dim == 1 ? 150 : dim == 2 ? 500 : 800, axes, 5u);
    for (int k : {1, 2 * dim, 7}) {
      const std::vector<Real> d = minimum_image_kth_neighbour_distance(c, k);
      const auto ref = brute_force(c, 0.45);  // every minimum-image pair within 0.45 (< half the shortest period)
      ASSERT_EQ(d.size(), static_cast<std::size_t>(c.size()));
      Index shorter = 0;
      const std::vector<Real> plain = kth_neighbour_distance(c, k);
      for (Index i = 0; i < c.size(); ++i) {
        std::vector<Real> dist;
        for (const auto& [j, code] : ref[static_cast<std::size_t>(i)])
          dist.push_back((c.positions[static_cast<std::size_t>(j)] + periodic_shift(c.domain, code) - c.positions[static_cast<std::size_t>(i)]).norm());
        ASSERT_GE(dist.size(), static_cast<std::size_t>(k)) << axes << " particle " << i;
        std::nth_element(dist.begin(), dist.begin() + (k - 1), dist.end());
        EXPECT_NEAR(d[static_cast<std::size_t>(i)], dist[static_cast<std::size_t>(k - 1)], 1e-14) << axes << " k " << k << " particle " << i;
        EXPECT_LE(d[static_cast<std::size_t>(i)], plain[static_cast<std::size_t>(i)]);
        shorter += d[static_cast<std::size_t>(i)] < plain[static_cast<std::size_t>(i)];
      }
      if (k == 7) {
        EXPECT_GT(shorter, 0) << axes;  // some particles saw nearer neighbours across a face
      }
    }
  }
  // A lattice periodic in x and y: every particle has its four nearest at dx (plainly, a
  // particle on an edge of the box has three, its fourth at dx √2).
  PointCloud lattice;
  lattice.dim = 2;
  lattice.domain = Domain::unit_box(2);
  lattice.domain.set_periodic("x,y");
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) lattice.add(Vec3(0.1 * i, 0.1 * j, 0), Tag::Interior);
  for (Real r : minimum_image_kth_neighbour_distance(lattice, 4)) EXPECT_NEAR(r, 0.1, 1e-12);
  EXPECT_NEAR(kth_neighbour_distance(lattice, 4)[5], 0.1 * std::sqrt(2.0), 1e-12);  // (0, 0.5)
  // Too few particles across the box: the k-th neighbour half a period away.
  PointCloud sparse = random_periodic_cloud(2, 6, "x,y", 2u);
  EXPECT_THROW_MSG(minimum_image_kth_neighbour_distance(sparse, 5), ConfigError, "too few particles across the periodic box");
}

TEST(PeriodicSearch, RefusesAShortPeriodAndParticlesOutsideTheBox) {
  PointCloud c = random_periodic_cloud(2, 100, "x,y", 3u);
  SearchParams sp;
  sp.radius = 0.5;  // the y period is 1: not larger than 2 h
  sp.min_neighbours = 0;
  EXPECT_THROW_MSG(find_neighbours(c, sp), InputError, "periodic axis y: the period 1 must be larger than twice");
  sp.radius = 0.1;
  c.positions[7][0] = 2.0;  // hi is the image of lo: outside [lo, hi)
  EXPECT_THROW_MSG(find_neighbours(c, sp), InputError, "particle 7 at (2, ");
  c.positions[7] = c.domain.wrap(c.positions[7]);
  EXPECT_EQ(c.positions[7][0], 0.0);
  EXPECT_NO_THROW(find_neighbours(c, sp));
}

TEST(PeriodicDomain, AxesParsedAndBoundaryOnlyOnOtherAxes) {
  Domain d = Domain::unit_box(3);
  d.set_periodic("x,z");
  EXPECT_EQ(d.periodic_axes(), "x,z");
  EXPECT_FALSE(d.fully_periodic());
  EXPECT_NEAR(d.signed_distance(Vec3(0.01, 0.3, 0.02)), 0.3, 1e-15);  // only the y faces bound it
  EXPECT_THROW_MSG(d.set_periodic("w"), ConfigError, "periodic axes are x, y, z or all");
  Domain two = Domain::unit_box(2);
  EXPECT_THROW_MSG(two.set_periodic("z"), ConfigError, "periodic axis z does not exist in 2D");
  two.set_periodic("all");
  EXPECT_TRUE(two.fully_periodic());
}

TEST(PeriodicDomain, LatticesHaveNoParticlesOnPeriodicFaces) {
  Domain box = Domain::unit_box(2);
  box.set_periodic("x");
  const PointCloud v = vertex_lattice(box, 8);
  EXPECT_EQ(v.size(), 8 * 9);                                   // x: 0..7/8, y: 0..1
  EXPECT_EQ(v.count(Tag::Dirichlet), 16);                       // the y faces only
  for (std::size_t i = 0; i < v.positions.size(); ++i) {
    EXPECT_LT(v.positions[i][0], 1.0);
    if (v.tags[i] == Tag::Dirichlet) {
      EXPECT_NEAR(std::abs(v.normals[i][1]), 1.0, 1e-15);
    }
  }
  box.set_periodic("all");
  PointCloud p = cell_centred_lattice(box, 8, true);
  EXPECT_EQ(p.size(), 64);
  EXPECT_EQ(p.count(Tag::Interior), 64);
  PerturbOptions po;
  po.delta = 0.5;
  perturb(p, po);  // moves across the faces wrap
  for (const Vec3& x : p.positions) {
    EXPECT_GE(x[0], 0.0);
    EXPECT_LT(x[0], 1.0);
    EXPECT_GE(x[1], 0.0);
    EXPECT_LT(x[1], 1.0);
  }
  EXPECT_EQ(p.count(Tag::Interior), 64);
}
