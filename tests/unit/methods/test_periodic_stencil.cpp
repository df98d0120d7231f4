// SPDX-License-Identifier: BSD-3-Clause
// periodic_stencil: a method's rows on a periodic box are the rows it builds on the box
// tiled with copies of itself (the middle copy's rows, columns taken modulo the copies),
// and Method::build refuses a neighbour list that crosses periodic faces.
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud periodic_cloud(int n) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(2);
  spec.box.set_periodic("all");
  spec.n = n;
  spec.delta = 0.4;
  spec.seed = 5;
  return make_study_cloud(spec).cloud;
}

// 3 x 3 copies, the original in the middle (copy 4), on a box that is not periodic.
PointCloud tiled(const PointCloud& c) {
  PointCloud t;
  t.dim = 2;
  t.spacing = c.spacing;
  t.domain = Domain::box(2, Vec3(-1, -1, 0), Vec3(2, 2, 0));
  for (int b = -1; b <= 1; ++b)
    for (int a = -1; a <= 1; ++a)
      for (const Vec3& x : c.positions) t.add(x + Vec3(a, b, 0), Tag::Interior);
  return t;
}
}  // namespace

TEST(PeriodicStencil, RowsAreThoseOfTheTiledBox) {
  const PointCloud c = periodic_cloud(12);
  const PointCloud t = tiled(c);
  const Index n = c.size();
  SearchParams sp;
  sp.radius = 3 * c.spacing;
  const NeighbourList tnl = find_neighbours(t, sp);
  // (VRSPH's NNLS has many solutions per row and may pick another in another column order:
  // its rows are checked by their moment conditions below.)
  // (gpm with Voronoi volumes: the cells of the periodic tessellation, the tiled box's middle
  // copy's cells.)
  for (const char* name : {"fpm", "cspm", "sph", "gpm"})
    for (OperatorKind kind : {OperatorKind::Laplacian, OperatorKind::Gradient}) {
      if (std::string(name) == "gpm" && !built_with("CGAL")) continue;  // Voronoi cells need CGAL
      MethodOptions options;
      if (std::string(name) == "gpm") options.set("volume", "voronoi");
      const auto method = builtin_methods().create(name, options);
      StencilRequest req;
      req.kind = kind;
      const Stencil p = periodic_stencil(*method, c, sp, KernelType::CubicSpline, c.spacing, req);
      std::vector<char> middle(static_cast<std::size_t>(t.size()), 0);
      std::fill(middle.begin() + 4 * n, middle.begin() + 5 * n, 1);
      StencilRequest treq = req;
      treq.rows = middle;
      const Stencil ref = method->build({t, tnl, KernelType::CubicSpline, c.spacing, n}, treq);
      ASSERT_EQ(p.rows(), n);
      for (Index i = 0; i < n; ++i) {
        // The reference row over the originals (modulo the copies), as a dense row.
        std::vector<std::vector<Real>> want(p.values.size(), std::vector<Real>(static_cast<std::size_t>(n), 0.0));
        for (Index k = ref.row_begin(4 * n + i); k < ref.row_end(4 * n + i); ++k)
          for (std::size_t c2 = 0; c2 < ref.values.size(); ++c2)
            want[c2][static_cast<std::size_t>(ref.col[static_cast<std::size_t>(k)] % n)] += ref.values[c2][static_cast<std::size_t>(k)];
        for (Index k = p.row_begin(i); k < p.row_end(i); ++k)
          for (std::size_t c2 = 0; c2 < p.values.size(); ++c2)
            want[c2][static_cast<std::size_t>(p.col[static_cast<std::size_t>(k)])] -= p.values[c2][static_cast<std::size_t>(k)];
        Real scale = 0, diff = 0;
        for (Index k = ref.row_begin(4 * n + i); k < ref.row_end(4 * n + i); ++k)
          scale = std::max(scale, std::abs(ref.values[0][static_cast<std::size_t>(k)]));
        for (const auto& comp : want)
          for (Real d : comp) diff = std::max(diff, std::abs(d));
        ASSERT_LE(diff, 1e-9 * scale) << name << " " << to_string(kind) << " row " << i;
        EXPECT_EQ(p.col[static_cast<std::size_t>(p.diag[static_cast<std::size_t>(i)])], i);
      }
    }
}

// VRSPH's Laplacian rows meet their moment conditions across the faces: with d_ij the
// minimum-image vector, sum_j w_ij d_ij = 0 and sum_j w_ij d_ij d_ij^T = 2 I.
TEST(PeriodicStencil, VrsphMomentConditionsAcrossTheFaces) {
  const PointCloud c = periodic_cloud(12);
  SearchParams sp;
  sp.radius = 3 * c.spacing;
  const auto method = builtin_methods().create("vrsph");
  const Stencil s = periodic_stencil(*method, c, sp, KernelType::CubicSpline, c.spacing, StencilRequest{});
  Index across = 0;
  for (Index i = 0; i < s.rows(); ++i) {
    Eigen::Vector2d first = Eigen::Vector2d::Zero();
    Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
    Real scale = 0;
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
      const auto sk = static_cast<std::size_t>(k);
      Vec3 d = c.positions[static_cast<std::size_t>(s.col[sk])] - c.positions[static_cast<std::size_t>(i)];
      for (int a = 0; a < 2; ++a) d[a] -= std::round(d[a]);  // the minimum image (period 1)
      across += std::abs(c.positions[static_cast<std::size_t>(s.col[sk])][0] - c.positions[static_cast<std::size_t>(i)][0]) > 0.5;
      const Real w = s.values[0][sk];
      first += w * d.head<2>();
      second += w * d.head<2>() * d.head<2>().transpose();
      scale = std::max(scale, std::abs(w) * d.squaredNorm());
    }
    EXPECT_LT(first.norm(), 1e-8 * scale / (3 * c.spacing)) << "row " << i;
    EXPECT_LT((second - 2 * Eigen::Matrix2d::Identity()).norm(), 1e-8 * std::max(scale, 2.0)) << "row " << i;
  }
  EXPECT_GT(across, 0);
}

TEST(PeriodicStencil, ListsAcrossPeriodicFacesOnlyWhereAMethodReadsPairVectors) {
  const PointCloud c = periodic_cloud(10);
  SearchParams sp;
  sp.radius = 3 * c.spacing;
  const NeighbourList nl = find_neighbours(c, sp);
  ASSERT_FALSE(nl.shifts.empty());
  const Discretisation disc{c, nl, KernelType::CubicSpline, c.spacing};
  EXPECT_THROW_MSG(builtin_methods().create("brookshaw")->build(disc, StencilRequest{}), ConfigError,
                   "build the stencil with periodic_stencil()");
  // SPH's, CSPM's, Chen–Beraun's, GPM's and MPS's rows read distances, pair vectors, the neighbours' volumes (Shepard
  // sums over each neighbour's own list, Voronoi cells and |Ω|/N of the periodic box) and
  // coefficient values: the list gives the rows the images give, for every operator and volume.
  const Field coefficient = Field::LinSpaced(c.size(), 1.0, 2.0);
  for (const auto& [name, volume] : {std::pair{"sph", "dx"}, std::pair{"sph", "shepard"}, std::pair{"gpm", "lattice"},
                                     std::pair{"gpm", "shepard"}, std::pair{"gpm", "uniform"}, std::pair{"gpm", "voronoi"},
                                     std::pair{"mps", "lattice"}, std::pair{"mps", "uniform"}, std::pair{"cspm", "dx"},
                                     std::pair{"cspm", "shepard"}, std::pair{"chen-beraun", "dx"}, std::pair{"fpm", "shepard"},
                                     std::pair{"kgf", "shepard"}}) {
    if (std::string(volume) == "voronoi" && !built_with("CGAL")) continue;  // Voronoi cells need CGAL
    MethodOptions o;
    o.set("volume", volume);
    const auto method = builtin_methods().create(name, o);
    for (const OperatorKind kind : {OperatorKind::Value, OperatorKind::Gradient, OperatorKind::Laplacian, OperatorKind::DivAGrad}) {
      if (!method->info().supports(kind)) continue;
      StencilRequest req{kind};
      if (kind == OperatorKind::DivAGrad) req.coefficient = &coefficient;
      if (!method->reads_periodic_pairs(req)) {  // FPM's and KGF's div(a grad): on the images
        ASSERT_TRUE(std::string(name) == "fpm" || std::string(name) == "kgf") << name;
        continue;
      }
      const Stencil direct = method->build(disc, req);
      const Stencil images = periodic_stencil(*method, c, sp, KernelType::CubicSpline, c.spacing, req);
      for (std::size_t comp = 0; comp < images.values.size(); ++comp) {
        const SparseMatrix x(as_eigen(direct, static_cast<int>(comp))), y(as_eigen(images, static_cast<int>(comp)));
        EXPECT_LT((x - y).norm(), 1e-12 * y.norm()) << name << " " << volume << " " << to_string(kind) << " component " << comp;
      }
    }
  }
  const Field a_field = Field::LinSpaced(c.size(), 1.0, 2.0);
  StencilRequest divagrad{OperatorKind::DivAGrad};
  divagrad.coefficient = &a_field;
  EXPECT_THROW_MSG(builtin_methods().create("fpm")->build(disc, divagrad), ConfigError,
                   "build the stencil with periodic_stencil()");
  // FPM's rows with v = dx^d (a flow's gradient) read pair vectors: the list gives the rows the
  // images give.
  MethodOptions quadratic;
  quadratic.set("gradient_order", "2");
  const auto fpm = builtin_methods().create("fpm", quadratic);
  for (const OperatorKind kind : {OperatorKind::Gradient, OperatorKind::Laplacian}) {
    const StencilRequest req{kind};
    ASSERT_TRUE(fpm->reads_periodic_pairs(req));
    const Stencil direct = fpm->build(disc, req);
    const Stencil images = periodic_stencil(*fpm, c, sp, KernelType::CubicSpline, c.spacing, req);
    const SparseMatrix a(as_eigen(direct, 0)), b(as_eigen(images, 0));
    EXPECT_LT((a - b).norm(), 1e-9 * b.norm()) << to_string(kind);
  }
  // VRSPH's point rows read pair vectors only and take the list (Operators on periodic boxes);
  // its compact rows (a boundary value problem's) do not.
  const auto vrsph = builtin_methods().create("vrsph");
  StencilRequest system;
  system.use = StencilUse::System;
  EXPECT_FALSE(vrsph->reads_periodic_pairs(system));
  EXPECT_THROW_MSG(vrsph->build(disc, system), ConfigError, "build them with periodic_stencil()");
  ASSERT_TRUE(vrsph->reads_periodic_pairs(StencilRequest{}));
  const Stencil direct = vrsph->build(disc, StencilRequest{});
  const Stencil images = periodic_stencil(*vrsph, c, sp, KernelType::CubicSpline, c.spacing, StencilRequest{});
  for (Index i = 0; i < c.size(); ++i)
    EXPECT_NEAR(direct.residual[static_cast<std::size_t>(i)], images.residual[static_cast<std::size_t>(i)], 1e-9);
}
