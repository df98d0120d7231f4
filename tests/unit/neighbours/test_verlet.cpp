// SPDX-License-Identifier: BSD-3-Clause
// Verlet-skin lists: after every move, entry for entry the fresh search on the same positions
// (indices, distances and periodic shifts bit for bit), both paths (re-filter and search)
// taken; the refusals of a fresh search and of a cloud of another size.
#include <cmath>
#include <random>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/verlet.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud verlet_cloud(int dim, const std::string& periodic) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(dim);
  spec.box.set_periodic(periodic);
  spec.n = dim == 3 ? 10 : dim == 2 ? 24 : 60;
  spec.seed = 5;
  return make_study_cloud(spec).cloud;
}

void expect_same_list(const NeighbourList& a, const NeighbourList& b) {
  ASSERT_EQ(a.offsets, b.offsets);
  ASSERT_EQ(a.indices.size(), b.indices.size());
  for (std::size_t k = 0; k < a.indices.size(); ++k) {
    ASSERT_EQ(a.indices[k], b.indices[k]) << k;
    ASSERT_EQ(a.distances[k], b.distances[k]) << k;  // bit for bit
  }
  EXPECT_EQ(a.shifts, b.shifts);
  EXPECT_EQ(a.radii, b.radii);
}
}  // namespace

class VerletList : public ::testing::TestWithParam<std::tuple<int, std::string>> {};

TEST_P(VerletList, EqualsAFreshSearchAfterEveryMove) {
  const auto [dim, periodic] = GetParam();
  PointCloud c = verlet_cloud(dim, periodic);
  const Real dx = 1.0 / (dim == 3 ? 10 : dim == 2 ? 24 : 60);
  SearchParams sp;
  sp.radius = 2.5 * dx;
  VerletNeighbours verlet(sp, 0.4 * dx);
  std::mt19937 rng(7u);
  std::normal_distribution<double> step(0, 0.04 * dx);
  for (int s = 0; s < 12; ++s) {
    expect_same_list(verlet.update(c), find_neighbours(c, sp));
    for (Index i = 0; i < c.size(); ++i) {  // a drift along x (crossing the periodic face) plus noise
      Vec3& x = c.positions[static_cast<std::size_t>(i)];
      if (c.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
      for (int k = 0; k < dim; ++k) x[k] += step(rng) + (k == 0 && !periodic.empty() ? 0.05 * dx : 0);
      x = c.domain.wrap(x);
    }
  }
  EXPECT_GE(verlet.refilters(), 3);  // both paths taken
  EXPECT_GE(verlet.searches(), 2);
}

INSTANTIATE_TEST_SUITE_P(Clouds, VerletList,
                         ::testing::Values(std::make_tuple(2, std::string()), std::make_tuple(3, std::string()),
                                           std::make_tuple(2, std::string("x,y")), std::make_tuple(2, std::string("x")),
                                           std::make_tuple(1, std::string())));

TEST(VerletList, NewRadiiEqualAFreshSearchWithThemWhetherTheyGrowOrShrink) {
  // Larger radii than the candidates were searched with force a search; smaller ones only
  // re-filter. Either way the list is find_neighbours' with those radii, entry for entry.
  for (const std::string periodic : {"", "x,y"}) {
    PointCloud c = verlet_cloud(2, periodic);
    const Real dx = 1.0 / 24;
    SearchParams sp;
    sp.radius = 2.5 * dx;
    VerletNeighbours verlet(sp, 0.4 * dx);
    verlet.update(c);
    std::vector<Real> radii(static_cast<std::size_t>(c.size()));
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = (i % 3 == 0 ? 3.5 : 2.5) * dx;  // some grow
    verlet.set_radii(radii);
    const Index searched = verlet.searches();
    SearchParams fresh = sp;
    fresh.radii = radii;
    expect_same_list(verlet.update(c), find_neighbours(c, fresh));
    EXPECT_EQ(verlet.searches(), searched + 1) << periodic;
    std::vector<Real> larger = radii;  // grown and set back before an update: no search needed
    for (Real& r : larger) r *= 1.5;
    verlet.set_radii(larger);
    verlet.set_radii(radii);
    expect_same_list(verlet.update(c), find_neighbours(c, fresh));
    EXPECT_EQ(verlet.searches(), searched + 1) << periodic;
    for (Real& r : radii) r = 2.2 * dx;  // all shrink: re-filtered
    verlet.set_radii(radii);
    fresh.radii = radii;
    expect_same_list(verlet.update(c), find_neighbours(c, fresh));
    EXPECT_EQ(verlet.searches(), searched + 1) << periodic;
    EXPECT_EQ(verlet.radii(), radii);
  }
}

TEST(VerletList, RefusesRadiiThatDoNotFit) {
  PointCloud c = verlet_cloud(2, "x,y");
  SearchParams sp;
  sp.radius = 0.1;
  VerletNeighbours verlet(sp, 0.02);
  EXPECT_THROW_MSG(verlet.set_radii({0.1}), InputError, "after the first update");
  verlet.update(c);
  const std::vector<Real> before = verlet.radii();
  EXPECT_THROW_MSG(verlet.set_radii({0.1, 0.1}), InputError, "2 radii for");
  std::vector<Real> bad = before;
  bad[4] = -1;
  EXPECT_THROW_MSG(verlet.set_radii(bad), InputError, "particle 4 must be positive and finite");
  bad[4] = std::nan("");
  EXPECT_THROW_MSG(verlet.set_radii(bad), InputError, "particle 4 must be positive and finite");
  bad[4] = 0.49;  // plus the skin: over half the unit period
  EXPECT_THROW_MSG(verlet.set_radii(bad), InputError, "half the box's shortest period");
  EXPECT_EQ(verlet.radii(), before);
}

TEST(VerletList, RefusesWhatAFreshSearchRefusesAndAnotherCloud) {
  PointCloud c = verlet_cloud(2, "");
  SearchParams sp;
  sp.radius = 0.1;
  VerletNeighbours verlet(sp, 0.02);
  verlet.update(c);
  PointCloud moved = c;
  moved.positions[5] = moved.positions[6];  // a duplicate within the skin: the re-filter catches it
  EXPECT_THROW(verlet.update(moved), InputError);
  moved = c;
  moved.positions[3][0] = std::nan("");
  EXPECT_THROW(verlet.update(moved), InputError);
  moved = c;
  moved.add(Vec3(0.5, 0.5, 0), Tag::Interior);
  EXPECT_THROW(verlet.update(moved), InputError);
  expect_same_list(verlet.update(c), find_neighbours(c, sp));  // still usable
  EXPECT_THROW(VerletNeighbours(sp, -1), InputError);
  EXPECT_THROW(VerletNeighbours(sp, std::nan("")), InputError);
  PointCloud p = verlet_cloud(2, "x,y");
  VerletNeighbours pv(sp, 0.02);
  pv.update(p);
  p.positions[0][0] = 1.2;  // outside the periodic box
  EXPECT_THROW(pv.update(p), InputError);
}
