// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(Generate, VertexLatticeLayoutA) {
  for (int dim = 1; dim <= 3; ++dim) {
    const int n = 6;
    const PointCloud c = vertex_lattice(Domain::unit_box(dim), n);
    EXPECT_EQ(c.size(), static_cast<Index>(std::pow(n + 1, dim)));
    EXPECT_EQ(c.count(Tag::Interior), static_cast<Index>(std::pow(n - 1, dim)));
    EXPECT_EQ(c.count(Tag::Ghost), 0);
    EXPECT_DOUBLE_EQ(c.spacing, 1.0 / n);
    for (Index i = 0; i < c.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (c.tags[si] != Tag::Dirichlet) continue;
      EXPECT_NEAR(c.normals[si].norm(), 1.0, 1e-12);
      EXPECT_NEAR(c.domain.signed_distance(c.positions[si]), 0.0, 1e-14);
      // The normal points outward: a small step along it leaves the box.
      EXPECT_LT(c.domain.signed_distance(c.positions[si] + 1e-3 * c.normals[si]), 0);
    }
    EXPECT_NO_THROW(validate(c));
  }
}

TEST(Generate, CellCentredLatticeLayoutBAndGhosts) {
  const PointCloud b = cell_centred_lattice(Domain::unit_box(2), 5, true);
  EXPECT_EQ(b.size(), 49);  // (5+2)^2: centres, face centres and corners
  EXPECT_EQ(b.count(Tag::Interior), 25);
  EXPECT_EQ(b.count(Tag::Dirichlet), 24);
  const PointCloud g = cell_centred_lattice(Domain::symmetric_box(2, 1), 8, false, 3);
  EXPECT_EQ(g.size(), 14 * 14);
  EXPECT_EQ(g.count(Tag::Interior), 64);
  EXPECT_EQ(g.count(Tag::Ghost), 14 * 14 - 64);
  EXPECT_EQ(ghost_layers_for(0.75, 0.25), 4);
}

TEST(Generate, PerturbationIsSeededBoundedAndKeepsBoundaryFixed) {
  const PointCloud base = vertex_lattice(Domain::unit_box(2), 10);
  PointCloud a = base, b = base, c = base;
  perturb(a, {0.5, 42, false});
  perturb(b, {0.5, 42, false});
  perturb(c, {0.5, 43, false});
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_NE(a.positions, c.positions);
  double max_step = 0;
  for (Index i = 0; i < a.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3 d = a.positions[si] - base.positions[si];
    if (base.tags[si] == Tag::Dirichlet) EXPECT_EQ(d.norm(), 0.0);
    else EXPECT_GT(a.domain.signed_distance(a.positions[si]), 0.0);
    max_step = std::max(max_step, d.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_step, 0.5 * base.spacing);
  EXPECT_GT(max_step, 0.4 * base.spacing);
  // Tangential boundary perturbation: face particles stay on their face.
  PointCloud t = base;
  perturb(t, {0.5, 42, true});
  int moved = 0;
  for (Index i = 0; i < t.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (t.tags[si] != Tag::Dirichlet) continue;
    EXPECT_NEAR(t.domain.signed_distance(t.positions[si]), 0.0, 1e-15);
    moved += (t.positions[si] - base.positions[si]).norm() > 0;
  }
  EXPECT_GT(moved, 20);
  EXPECT_THROW_MSG(perturb(t, {1.5, 1, false}), ConfigError, "delta must be in [0, 1)");
}

TEST(Generate, BallCloud) {
  for (int dim = 1; dim <= 3; ++dim) {
    const PointCloud c = ball_cloud(dim, 0.5, 10);
    EXPECT_GT(c.count(Tag::Interior), 0);
    for (Index i = 0; i < c.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      const double sd = c.domain.signed_distance(c.positions[si]);
      if (c.tags[si] == Tag::Dirichlet) {
        EXPECT_NEAR(sd, 0.0, 1e-14);
        EXPECT_NEAR(c.normals[si].dot(c.positions[si] / 0.5), 1.0, 1e-12);
      } else {
        EXPECT_GE(sd, 0.5 * c.spacing - 1e-12);
      }
    }
  }
}

// The interior is every lattice point at least dx/2 inside (x outermost), as a direct scan
// finds them; parts made alone are slices of the whole cloud.
TEST(Generate, BallCloudRowsAndParts) {
  for (int dim = 1; dim <= 3; ++dim)
    for (int n : {2, 7, 12}) {
      const Real radius = 0.75, dx = 2 * radius / n;
      const PointCloud c = ball_cloud(dim, radius, n);
      ASSERT_EQ(ball_cloud_size(dim, radius, n), c.size());
      std::vector<Vec3> scan;
      const int m = n / 2 + 1;
      for (int k = -m; k <= m; ++k)
        for (int j = dim > 1 ? -m : 0; j <= (dim > 1 ? m : 0); ++j)
          for (int i = dim > 2 ? -m : 0; i <= (dim > 2 ? m : 0); ++i)
            if (c.domain.signed_distance(Vec3(k * dx, j * dx, i * dx)) >= 0.5 * dx - 1e-12 * dx)
              scan.emplace_back(k * dx, j * dx, i * dx);
      ASSERT_EQ(c.count(Tag::Interior), static_cast<Index>(scan.size())) << dim << "D n=" << n;
      for (std::size_t p = 0; p < scan.size(); ++p) ASSERT_EQ(c.positions[p], scan[p]);
      for (Index p = static_cast<Index>(scan.size()); p < c.size(); ++p) {
        const auto sp = static_cast<std::size_t>(p);
        ASSERT_EQ(c.tags[sp], Tag::Dirichlet);
        ASSERT_NEAR(c.positions[sp].norm(), radius, 1e-14);
        ASSERT_EQ(c.positions[sp], radius * c.normals[sp]);
      }
      Index cuts[] = {0, 1, c.size() / 3, static_cast<Index>(scan.size()), c.size() - 1, c.size()};
      std::sort(std::begin(cuts), std::end(cuts));
      for (std::size_t a = 0; a + 1 < std::size(cuts); ++a) {
        const PointCloud part = ball_cloud(dim, radius, n, {cuts[a], cuts[a + 1]});
        ASSERT_EQ(part.size(), cuts[a + 1] - cuts[a]);
        for (Index p = 0; p < part.size(); ++p) {
          ASSERT_EQ(part.positions[static_cast<std::size_t>(p)], c.positions[static_cast<std::size_t>(cuts[a] + p)]);
          ASSERT_EQ(part.tags[static_cast<std::size_t>(p)], c.tags[static_cast<std::size_t>(cuts[a] + p)]);
        }
      }
      EXPECT_THROW((void)ball_cloud(dim, radius, n, {0, c.size() + 1}), ConfigError);
    }
}

TEST(Generate, MeshCentroidsHaveShortEdgesAndLieInTheMesh) {
  VRSPH_REQUIRE_PART("CGAL");
  for (int dim = 2; dim <= 3; ++dim) {
    double max_edge = 0;
    const double dx = dim == 2 ? 0.1 : 0.25;
    const PointCloud c = mesh_centroids(Domain::unit_box(dim), dx, 3, 0.0, true, &max_edge);
    EXPECT_LT(max_edge, dx);
    EXPECT_GT(max_edge, 0.5 * dx);
    EXPECT_GT(c.count(Tag::Interior), 0);
    EXPECT_GT(c.count(Tag::Dirichlet), 0);
    EXPECT_EQ(c.count(Tag::Ghost), 0);
    for (Index i = 0; i < c.size(); ++i) EXPECT_GE(c.domain.signed_distance(c.positions[static_cast<std::size_t>(i)]), -1e-14);
    const PointCloud g = mesh_centroids(Domain::unit_box(dim), dx, 3, 2 * dx, false);
    EXPECT_GT(g.count(Tag::Ghost), 0);
    // Same seed, same mesh.
    EXPECT_EQ(mesh_centroids(Domain::unit_box(dim), dx, 3, 0.0, true).positions, c.positions);
  }
  EXPECT_THROW_MSG(mesh_centroids(Domain::unit_box(1), 0.1, 1, 0, true), InputError, "2D or 3D box");
}

TEST(Generate, RejectsBadArguments) {
  EXPECT_THROW_MSG(vertex_lattice(Domain::unit_box(2), 0), ConfigError, "must be >= 1, got 0");
  EXPECT_THROW_MSG(Domain::box(2, Vec3(0, 0, 0), Vec3(1, -1, 0)), InputError, "must exceed lower bound");
  EXPECT_THROW_MSG(ball_cloud(2, -1, 10), InputError, "radius must be positive");
  EXPECT_THROW_MSG(parse_tag("wall"), InputError, "unknown particle tag 'wall'");
}
