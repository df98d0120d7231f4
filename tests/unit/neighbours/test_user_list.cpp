// SPDX-License-Identifier: BSD-3-Clause
// A neighbour list from the caller (issue 33: "a neighbour list given by the user accepted, with
// distances computed when missing"): completed into the library's form, and refused by name
// when it contradicts the cloud.
#include <algorithm>
#include <vector>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/neighbours/user_list.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// A perturbed 11 x 11 lattice and the library's own list at h = 3 dx, to hand back as the caller's.
struct Searched {
  PointCloud cloud;
  Real h = 0;
  NeighbourList nl;
  std::vector<Index> offsets() const { return {nl.offsets.begin(), nl.offsets.end()}; }
  std::vector<Index> indices() const { return {nl.indices.begin(), nl.indices.end()}; }
};
Searched searched() {
  Searched s;
  s.cloud = vertex_lattice(Domain::unit_box(2), 10);
  perturb(s.cloud, {.delta = 0.3, .seed = 4});
  s.h = 3 * s.cloud.spacing;
  SearchParams p;
  p.radius = s.h;
  s.nl = find_neighbours(s.cloud, p);
  return s;
}
}  // namespace

TEST(UserNeighbours, ASearchedListComesBackEqualWithDistancesComputed) {
  const Searched s = searched();
  const std::vector<Index> off = s.offsets();
  std::vector<Index> idx = s.indices();
  // Rows in reverse order: the caller's order does not matter.
  for (Index i = 0; i < s.cloud.size(); ++i)
    std::reverse(idx.begin() + off[static_cast<std::size_t>(i)], idx.begin() + off[static_cast<std::size_t>(i) + 1]);
  const std::vector<Real> radius{s.h};
  const NeighbourList nl = neighbour_list_from(s.cloud, {off, idx, {}, radius});
  ASSERT_EQ(nl.offsets, s.nl.offsets);
  EXPECT_TRUE(std::equal(nl.indices.begin(), nl.indices.end(), s.nl.indices.begin()));
  EXPECT_TRUE(std::equal(nl.distances.begin(), nl.distances.end(), s.nl.distances.begin()));  // bitwise
  EXPECT_EQ(nl.radii, s.nl.radii);
  // A method reads it as its own search's list: the same VRSPH Laplacian, bitwise.
  const auto m = builtin_methods().create("vrsph");
  const Stencil a = m->build({s.cloud, s.nl, KernelType::CubicSpline, s.h}, {OperatorKind::Laplacian});
  const Stencil b = m->build({s.cloud, nl, KernelType::CubicSpline, s.h}, {OperatorKind::Laplacian});
  EXPECT_EQ(a.col, b.col);
  EXPECT_EQ(a.values, b.values);
}

TEST(UserNeighbours, ListsThatContradictTheCloudAreNamed) {
  const Searched s = searched();
  const std::vector<Index> off = s.offsets(), idx = s.indices();
  const std::vector<Real> radius{s.h};
  const auto with = [&](std::vector<Index> o, std::vector<Index> i, std::vector<Real> d = {}, std::vector<Real> r = {}) {
    const std::vector<Real> rr = r.empty() ? radius : r;
    return neighbour_list_from(s.cloud, {o, i, d, rr});
  };
  EXPECT_THROW_MSG(with({0, 1}, idx), InputError, "2 row offsets for 121 particles (122 expected)");
  std::vector<Index> bad = idx;
  bad[0] = 500;
  EXPECT_THROW_MSG(with(off, bad), InputError, "row 0 lists particle 500, outside 0..120");
  bad[0] = 0;
  EXPECT_THROW_MSG(with(off, bad), InputError, "row 0 lists the particle itself");
  bad = idx;
  bad[1] = bad[0];
  EXPECT_THROW_MSG(with(off, bad), InputError, "row 0 lists particle " + std::to_string(idx[0]) + " twice");
  bad = idx;
  bad[0] = 120;  // the far corner of the unit square
  EXPECT_THROW_MSG(with(off, bad), InputError, "not within the row's support radius");
  std::vector<Real> d(s.nl.distances.begin(), s.nl.distances.end());
  d.at(3) *= 1.01;  // (at: GCC cannot see that the list is not empty)
  EXPECT_THROW_MSG(with(off, idx, d), InputError, "is given as");
  EXPECT_THROW_MSG(with(off, idx, {}, {-1.0}), InputError, "support radius of particle 0 is -1");
  EXPECT_THROW_MSG(with(off, idx, {}, {1.0, 2.0}), InputError, "2 support radii for 121 particles");
  // Row 0 without its first neighbour j (the offsets shift): j still lists 0.
  std::vector<Index> o2 = off, i2 = idx;
  i2.erase(i2.begin());
  for (std::size_t k = 1; k < o2.size(); ++k) --o2[k];
  EXPECT_THROW_MSG(with(o2, i2), InputError, "lists particle 0 but row 0 does not list " + std::to_string(idx[0]));
  // No neighbours at all: refused as the search refuses it.
  EXPECT_THROW_MSG(with(std::vector<Index>(off.size(), 0), {}), GeometryError, "particle 0 at (0, 0, 0) has 0 neighbours");
  std::vector<Index> o3 = off;
  o3[5] = o3[4] - 1;
  EXPECT_THROW_MSG(with(o3, idx), InputError, "the row offsets decrease at particle 4");
}

// On a periodic box the caller's pairs go to the nearest image: the minimum-image search's
// list comes back entry for entry (indices, distances and shift codes, bitwise), the periodic
// stencil built from it equals the one on the library's search, and a pair listed on one side
// of a periodic face only is named.
TEST(UserNeighbours, PeriodicBoxPairsTakeTheNearestImage) {
  PointCloud c = vertex_lattice([] {
    Domain d = Domain::unit_box(2);
    d.set_periodic("all");
    return d;
  }(), 12);
  perturb(c, {.delta = 0.3, .seed = 6});
  const Real h = 3 * c.spacing;
  SearchParams p;
  p.radius = h;
  const NeighbourList ref = find_neighbours(c, p);
  ASSERT_EQ(ref.shifts.size(), static_cast<std::size_t>(ref.total()));
  const std::vector<Index> off(ref.offsets.begin(), ref.offsets.end()), idx(ref.indices.begin(), ref.indices.end());
  const std::vector<Real> radius{h};
  const NeighbourList nl = neighbour_list_from(c, {off, idx, {}, radius});
  ASSERT_EQ(nl.offsets, ref.offsets);
  EXPECT_TRUE(std::equal(nl.indices.begin(), nl.indices.end(), ref.indices.begin()));
  EXPECT_TRUE(std::equal(nl.distances.begin(), nl.distances.end(), ref.distances.begin()));
  EXPECT_EQ(nl.shifts, ref.shifts);
  EXPECT_GT(std::count_if(nl.shifts.begin(), nl.shifts.end(), [](std::uint8_t s) { return s != no_shift; }), 0);
  for (const char* name : {"vrsph", "fpm", "sph"}) {
    const auto m = builtin_methods().create(name);
    for (OperatorKind kind : {OperatorKind::Laplacian, OperatorKind::Gradient}) {
      StencilRequest req;
      req.kind = kind;
      const Stencil a = periodic_stencil(*m, c, p, KernelType::CubicSpline, c.spacing, req);
      const Stencil b = periodic_stencil(*m, c, nl, KernelType::CubicSpline, c.spacing, req);
      ASSERT_EQ(a.col, b.col) << name;
      ASSERT_EQ(a.values.size(), b.values.size());
      for (std::size_t comp = 0; comp < a.values.size(); ++comp)
        for (std::size_t k = 0; k < a.values[comp].size(); ++k)
          ASSERT_NEAR(a.values[comp][k], b.values[comp][k], 1e-9 * std::abs(a.values[comp][k]) + 1e-9) << name << " entry " << k;
    }
  }
  // Row 0 (at a corner of the box) loses a neighbour across a face; that neighbour's row keeps it.
  Index across = -1, at = -1;
  for (Index k = ref.offsets[0]; k < ref.offsets[1] && across < 0; ++k)
    if (ref.shifts[static_cast<std::size_t>(k)] != no_shift) {
      across = ref.indices[static_cast<std::size_t>(k)];
      at = k;
    }
  ASSERT_GE(across, 0);
  std::vector<Index> off2 = off, idx2 = idx;
  idx2.erase(idx2.begin() + at);
  for (std::size_t i = 1; i < off2.size(); ++i) off2[i] -= 1;
  EXPECT_THROW_MSG(neighbour_list_from(c, {off2, idx2, {}, radius}), InputError, "but row 0 does not list");
  // The period must exceed twice the radius, as for the search.
  const std::vector<Real> too_wide{0.6};
  EXPECT_THROW_MSG(neighbour_list_from(c, {off, idx, {}, too_wide}), InputError, "larger than twice the support radius");
  // Not a periodic list: refused by the periodic stencil.
  NeighbourList plain = nl;
  plain.shifts.clear();
  const auto m = builtin_methods().create("sph");
  EXPECT_THROW_MSG(periodic_stencil(*m, c, plain, KernelType::CubicSpline, c.spacing, {OperatorKind::Laplacian}),
                   InputError, "no periodic shift codes");
}
