// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// Lower bound: max nearest-particle distance over a fine sampling grid of the domain.
double sampled_lower_bound(const PointCloud& c, int per_axis) {
  const Domain& d = c.domain;
  const Vec3 lo = d.shape == Domain::Shape::Box ? d.lo : Vec3(d.centre - Vec3::Constant(d.radius));
  const Vec3 hi = d.shape == Domain::Shape::Box ? d.hi : Vec3(d.centre + Vec3::Constant(d.radius));
  double best = 0;
  const int ny = c.dim > 1 ? per_axis : 0, nz = c.dim > 2 ? per_axis : 0;
  for (int a = 0; a <= per_axis; ++a)
    for (int b = 0; b <= ny; ++b)
      for (int e = 0; e <= nz; ++e) {
        Vec3 x = Vec3::Zero();
        x[0] = lo[0] + (hi[0] - lo[0]) * a / per_axis;
        if (c.dim > 1) x[1] = lo[1] + (hi[1] - lo[1]) * b / per_axis;
        if (c.dim > 2) x[2] = lo[2] + (hi[2] - lo[2]) * e / per_axis;
        if (d.signed_distance(x) < 0) continue;
        double m = 1e300;
        for (const auto& p : c.positions) m = std::min(m, (p - x).norm());
        best = std::max(best, m);
      }
  return best;
}
}  // namespace

TEST(CoveringRadius, ExactOnLattices) {
  for (int dim = 1; dim <= 3; ++dim) {
    const PointCloud c = vertex_lattice(Domain::unit_box(dim), 8);
    EXPECT_NEAR(covering_radius(c).radius, std::sqrt(static_cast<double>(dim)) / 2 / 8, 1e-12) << dim << "D";
  }
}

TEST(CoveringRadius, BoundsSampledValuesOnIrregularClouds) {
  for (int dim = 1; dim <= 3; ++dim)
    for (auto fam : {CloudFamily::Perturbed, CloudFamily::Disk}) {
      CloudSpec spec;
      spec.family = fam;
      spec.box = Domain::unit_box(dim);
      spec.n = dim == 3 ? 6 : 12;
      spec.seed = 9;
      const StudyCloud sc = make_study_cloud(spec);
      const CoveringRadius r = covering_radius(sc.cloud);
      const int grid = dim == 1 ? 20000 : dim == 2 ? 400 : 60;
      const double lower = sampled_lower_bound(sc.cloud, grid);
      const double step = std::sqrt(static_cast<double>(dim)) / grid;  // sampling resolution
      SCOPED_TRACE(testing::Message() << dim << "D " << to_string(fam));
      EXPECT_GE(r.radius, lower - 1e-12);
      EXPECT_LE(r.radius, lower + step);
      EXPECT_GE(sc.cloud.domain.signed_distance(r.point), -1e-12);
    }
}

// METHODS P15: on lattices perturbed by U(-dx/2, dx/2), r_N is about 1.0-1.2 dx.
TEST(CoveringRadius, PerturbedLatticeIsAboutOneSpacing) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.n = 80;
  spec.seed = 2;
  const StudyCloud sc = make_study_cloud(spec);
  const double ratio = covering_radius(sc.cloud).radius / sc.dx;
  EXPECT_GT(ratio, 0.9);
  EXPECT_LT(ratio, 1.3);
}

// A box periodic along some axes: the largest empty ball of the periodic point set, against a
// sampling with minimum-image distances (unit periods), the same when the cloud is moved along
// the periodic axes; a periodic lattice's is half its cell diagonal.
TEST(CoveringRadius, PeriodicBoxesAcrossTheirFaces) {
  for (const auto& [dim, axes] : {std::pair{1, "x"}, std::pair{2, "x,y"}, std::pair{2, "y"}, std::pair{3, "x,z"}}) {
    CloudSpec spec;
    spec.family = CloudFamily::Perturbed;
    spec.box = Domain::unit_box(dim);
    spec.box.set_periodic(axes);
    spec.n = dim == 3 ? 6 : 12;
    spec.seed = 4;
    const PointCloud c = make_study_cloud(spec).cloud;
    const CoveringRadius r = covering_radius(c);
    const int grid = dim == 1 ? 20000 : dim == 2 ? 300 : 50;
    double lower = 0;
    const int ny = dim > 1 ? grid : 0, nz = dim > 2 ? grid : 0;
    for (int a = 0; a <= grid; ++a)
      for (int b = 0; b <= ny; ++b)
        for (int e = 0; e <= nz; ++e) {
          const Vec3 x(static_cast<double>(a) / grid, dim > 1 ? static_cast<double>(b) / grid : 0.0,
                       dim > 2 ? static_cast<double>(e) / grid : 0.0);
          double m = 1e300;
          for (const auto& p : c.positions) {
            Vec3 d = p - x;
            for (int k = 0; k < dim; ++k)
              if (c.domain.periodic[static_cast<std::size_t>(k)]) d[k] -= std::round(d[k]);
            m = std::min(m, d.norm());
          }
          lower = std::max(lower, m);
        }
    SCOPED_TRACE(axes);
    EXPECT_GE(r.radius, lower - 1e-12);
    EXPECT_LE(r.radius, lower + std::sqrt(static_cast<double>(dim)) / grid);
    for (int k = 0; k < dim; ++k) {  // the point where it is attained lies in the box
      EXPECT_GE(r.point[k], 0.0);
      EXPECT_LE(r.point[k], 1.0);
    }
    PointCloud moved = c;
    for (auto& x : moved.positions) {
      for (int k = 0; k < dim; ++k)
        if (c.domain.periodic[static_cast<std::size_t>(k)]) x[k] += 0.31 + 0.1 * k;
      x = moved.domain.wrap(x);
    }
    EXPECT_NEAR(covering_radius(moved).radius, r.radius, 1e-12);
  }
  for (int dim = 1; dim <= 3; ++dim) {
    PointCloud lattice = cell_centred_lattice(Domain::unit_box(dim), 8, false);
    lattice.domain.set_periodic("all");
    EXPECT_NEAR(covering_radius(lattice).radius, std::sqrt(static_cast<double>(dim)) / 2 / 8, 1e-12) << dim << "D";
  }
}

TEST(CoveringRadius, NeedsADomain) {
  PointCloud c = vertex_lattice(Domain::unit_box(2), 4);
  c.domain = Domain{};
  EXPECT_THROW_MSG(covering_radius(c), InputError, "needs a box or ball domain");
}

TEST(Smoothing, RulesGiveTheDocumentedRadii) {
  const PointCloud lattice = vertex_lattice(Domain::unit_box(2), 10);
  EXPECT_DOUBLE_EQ(choose_smoothing(lattice, 0.1, 3, SmoothingMode::Fixed).h, 0.3);
  // Uniform lattice: r_N = dx/sqrt(2) < dx, so covering = fixed.
  const SmoothingChoice cov = choose_smoothing(lattice, 0.1, 3, SmoothingMode::Covering);
  EXPECT_NEAR(cov.covering_radius, 0.1 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(cov.h, 0.3, 1e-12);
  // knn with k = 2d = 4: the 4th neighbour of an interior lattice particle is at dx.
  const SmoothingChoice knn = choose_smoothing(lattice, 0.1, 3, SmoothingMode::Knn);
  ASSERT_EQ(knn.radii.size(), 121u);
  EXPECT_NEAR(knn.radii[60], 0.3, 1e-12);
  EXPECT_THROW_MSG(parse_smoothing_mode("adaptive"), ConfigError, "unknown smoothing-radius mode 'adaptive'");
  EXPECT_THROW_MSG(choose_smoothing(lattice, 0.1, -1, SmoothingMode::Fixed), ConfigError, "h-factor must be positive");
}
