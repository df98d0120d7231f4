// SPDX-License-Identifier: BSD-3-Clause
// support_isotropy (analysis/support_isotropy.hpp): 1 inside a lattice (its neighbourhoods are
// symmetric under the exchange of the axes), lower but far from 0 at its faces, the ratio of the
// moments on a lattice stretched by s along x and 1/s along y, 0 once the stretched columns are
// farther apart than the radius, the periodic images seen across a face, pairs of a Verlet list
// beyond the radius left out, and lists that do not belong to the cloud refused.
#include <algorithm>
#include <cmath>
#include <vrsph/analysis/support_isotropy.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

NeighbourList isotropy_search(const PointCloud& c, Real radius) {
  SearchParams sp;
  sp.radius = radius;
  return find_neighbours(c, sp);
}

PointCloud isotropy_lattice(int dim, int n, bool periodic) {
  Domain box = Domain::unit_box(dim);
  if (periodic) box.set_periodic("all");
  return periodic ? cell_centred_lattice(box, n, false) : vertex_lattice(box, n);
}

}  // namespace

TEST(SupportIsotropy, IsOneInsideALatticeAndFarFromZeroAtItsFacesInTwoAndThreeDimensions) {
  for (const int dim : {2, 3}) {
    const int n = dim == 2 ? 20 : 10;
    const Real h = 3.0 / n;
    const PointCloud c = isotropy_lattice(dim, n, false);
    const Field iso = support_isotropy(c, isotropy_search(c, h));
    ASSERT_EQ(iso.size(), c.size());
    Real inside_lo = 1, inside_hi = 0;
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& x = c.positions[static_cast<std::size_t>(i)];
      bool inside = true;
      for (int a = 0; a < dim; ++a) inside = inside && x[a] >= h - 1e-12 && x[a] <= 1 - h + 1e-12;
      if (!inside) continue;
      inside_lo = std::min(inside_lo, iso[i]);
      inside_hi = std::max(inside_hi, iso[i]);
    }
    EXPECT_NEAR(inside_lo, 1.0, 1e-12) << dim << "D";
    EXPECT_NEAR(inside_hi, 1.0, 1e-12) << dim << "D";
    // At a face the row along it counts along the face only (measured: 0.46 in 2D, 0.37 in 3D at
    // the corners); a support that still spans every direction.
    EXPECT_GT(iso.minCoeff(), 0.3) << dim << "D";
  }
}

TEST(SupportIsotropy, FallsAsOneOverTheStretchSquaredAndToZeroOnALine) {
  // A 2D lattice scaled by s along x and 1/s along y (the deformation of a saddle point's
  // strain): with a radius below s dx the only neighbours lie on the y-axis -> 0; with a larger
  // one the ratio is that of the moments, computed here from the pairs themselves.
  const int n = 20;
  PointCloud c = isotropy_lattice(2, n, false);
  const Real s = 2.0, dx = 1.0 / n;
  for (Vec3& x : c.positions) x = Vec3(s * x[0], x[1] / s, 0);
  c.domain = Domain::box(2, Vec3(0, 0, 0), Vec3(s, 1 / s, 0));
  // Radius 1.5 dx: neighbours at (0, ±k dx / 2) for k = 1, 2 only (the columns are 2 dx apart).
  const Real radius = 1.5 * dx;
  const Field line = support_isotropy(c, isotropy_search(c, radius));
  EXPECT_EQ(line.maxCoeff(), 0.0);
  // Radius 3 dx: columns at ±2 dx join. Interior particle: the ratio of the moments along y and x.
  const Real r3 = 3 * dx;
  const Field iso = support_isotropy(c, isotropy_search(c, r3));
  Real mxx = 0, myy = 0;
  for (int a = -3; a <= 3; ++a)
    for (int b = -12; b <= 12; ++b) {
      const Real x = a * s * dx, y = b * dx / s, r = std::hypot(x, y);
      if (r == 0 || !(r < r3)) continue;
      const Real w = (1 - r / r3) * (1 - r / r3);
      mxx += w * x * x;
      myy += w * y * y;
    }
  const Index centre = (n / 2) * (n + 1) + n / 2;
  EXPECT_NEAR(iso[centre], std::min(mxx, myy) / std::max(mxx, myy), 1e-12);
  EXPECT_LT(iso[centre], 0.99);
  // Stretched by 4: the columns are 4 dx apart and leave a support of 3 dx, whose neighbours now
  // all lie on the y-axis (the sheet of a saddle point's outflow).
  PointCloud far = isotropy_lattice(2, n, false);
  for (Vec3& x : far.positions) x = Vec3(4 * x[0], x[1] / 4, 0);
  far.domain = Domain::box(2, Vec3(0, 0, 0), Vec3(4, 0.25, 0));
  EXPECT_EQ(support_isotropy(far, isotropy_search(far, r3)).maxCoeff(), 0.0);
}

TEST(SupportIsotropy, SeesTheImagesAcrossPeriodicFacesAndLeavesOutPairsBeyondTheRadius) {
  const int n = 16;
  PointCloud c = isotropy_lattice(2, n, true);
  PerturbOptions po;
  po.delta = 0.3;
  po.seed = 3;
  perturb(c, po);
  const Real h = 3.0 / n;
  const NeighbourList nl = isotropy_search(c, h);
  ASSERT_FALSE(nl.shifts.empty());
  const Field iso = support_isotropy(c, nl);
  // The same particles translated by half a period (wrapped) have the same neighbourhoods: a
  // particle at a face sees across it as one in the middle does.
  PointCloud moved = c;
  for (Vec3& x : moved.positions) {
    x[0] = std::fmod(x[0] + 0.5, 1.0);
    x[1] = std::fmod(x[1] + 0.5, 1.0);
  }
  const Field iso_moved = support_isotropy(moved, isotropy_search(moved, h));
  for (Index i = 0; i < c.size(); ++i) EXPECT_NEAR(iso[i], iso_moved[i], 1e-12) << i;
  EXPECT_GT(iso.minCoeff(), 0.3);
  EXPECT_LT(iso.minCoeff(), 1.0);
  // A search with a larger radius whose rows claim the smaller one (a Verlet list's candidates):
  // the extra pairs take no part.
  NeighbourList wide = isotropy_search(c, 1.3 * h);
  std::fill(wide.radii.begin(), wide.radii.end(), h);
  const Field iso_wide = support_isotropy(c, wide);
  for (Index i = 0; i < c.size(); ++i) EXPECT_NEAR(iso[i], iso_wide[i], 1e-12) << i;
}

TEST(SupportIsotropy, RefusesAListOfAnotherCloud) {
  const PointCloud c = isotropy_lattice(2, 8, false);
  const PointCloud other = isotropy_lattice(2, 9, false);
  EXPECT_THROW((void)support_isotropy(c, isotropy_search(other, 3.0 / 9)), InputError);
  NeighbourList no_distances = isotropy_search(c, 3.0 / 8);
  no_distances.distances.clear();
  EXPECT_THROW((void)support_isotropy(c, no_distances), InputError);
}
