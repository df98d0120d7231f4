// SPDX-License-Identifier: BSD-3-Clause
// The generalized particle method of [IM]: with weight 2 (cubic spline) and lattice volumes it
// is SPH to round-off ([IM] (57)-(60), issue 12 item 2), in 1D-3D and on perturbed particles;
// weight 1 is monotone, weight 3 changes sign; constants are exact for every derivative.
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include <vrsph/methods/gpm/gpm.hpp>
#include <vrsph/methods/gpm/gpm_at.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct GpmCloud {
  PointCloud cloud;
  NeighbourList nl;
  explicit GpmCloud(int dim) {
    cloud = cell_centred_lattice(Domain::symmetric_box(dim, 1), dim == 3 ? 8 : 14, false, 4);
    perturb(cloud, {0.4, 5, false});
    SearchParams sp;
    sp.radius = 3 * cloud.spacing;
    nl = find_neighbours(cloud, sp);
  }
  Stencil build(const std::string& method, OperatorKind k, const MethodOptions& o = {}, const Field* a = nullptr) const {
    return builtin_methods().create(method, o)->build({cloud, nl, KernelType::CubicSpline, cloud.spacing}, {k, a});
  }
};
}  // namespace

TEST(Gpm, WeightTwoWithLatticeVolumesIsSph) {
  for (int dim = 1; dim <= 3; ++dim) {
    const GpmCloud c(dim);
    const Field a = Field::LinSpaced(c.cloud.size(), 1, 3);
    for (auto k : {OperatorKind::Value, OperatorKind::Gradient, OperatorKind::Laplacian, OperatorKind::DivAGrad, OperatorKind::Dy}) {
      if (k == OperatorKind::Dy && dim < 2) continue;
      const Stencil g = c.build("gpm", k, {}, &a), s = c.build("sph", k, {}, &a);
      ASSERT_EQ(g.col, s.col);
      for (std::size_t comp = 0; comp < g.values.size(); ++comp) {
        Real scale = 0, diff = 0;
        for (std::size_t e = 0; e < g.values[comp].size(); ++e) {
          scale = std::max(scale, std::abs(s.values[comp][e]));
          diff = std::max(diff, std::abs(g.values[comp][e] - s.values[comp][e]));
        }
        EXPECT_LT(diff, 1e-12 * scale) << dim << "D " << to_string(k) << " component " << comp;
      }
    }
  }
}

TEST(Gpm, SignsAndConstantsForEveryWeight) {
  const GpmCloud c(2);
  const Field one = Field::Ones(c.cloud.size());
  for (const char* weight : {"1", "2", "3"})
    for (const char* volume : {"lattice", "shepard"}) {
      if (std::string(weight) == "3" && std::string(volume) == "shepard") continue;  // pi3 changes sign
      MethodOptions o;
      o.set("weight", weight);
      o.set("volume", volume);
      const Stencil L = c.build("gpm", OperatorKind::Laplacian, o), G = c.build("gpm", OperatorKind::Gradient, o);
      EXPECT_LT(apply(L, one).cwiseAbs().maxCoeff(), 1e-9) << weight << volume;  // difference form
      EXPECT_LT(apply(G, one).cwiseAbs().maxCoeff(), 1e-9) << weight << volume;
      Index negative = 0;
      for (Index i = 0; i < c.cloud.size(); ++i)
        for (Index e = L.row_begin(i); e < L.row_end(i); ++e)
          if (L.col[static_cast<std::size_t>(e)] != i && L.values[0][static_cast<std::size_t>(e)] < 0) ++negative;
      if (std::string(weight) == "3") {
        EXPECT_GT(negative, 0);  // delta3 changes sign: no maximum principle
      } else {
        EXPECT_EQ(negative, 0) << weight << volume;
      }
    }
  MethodOptions bad;
  bad.set("weight", "4");
  EXPECT_THROW(c.build("gpm", OperatorKind::Laplacian, bad), ConfigError);
  MethodOptions shepard3;
  shepard3.set("weight", "3");
  shepard3.set("volume", "shepard");
  EXPECT_NO_THROW(c.build("gpm", OperatorKind::Laplacian, shepard3));  // pi3's sum is positive on this cloud
}

// mps against (61)-(62) summed directly, with an independent quadrature of lambda.
TEST(Mps, EqualsFormulas61And62) {
  for (const std::string weight : {"classic", "pi2"}) {
    PointCloud c = cell_centred_lattice(Domain::unit_box(2), 12, true);
    perturb(c, {.delta = 0.3, .seed = 4});
    SearchParams sp;
    sp.radius = 3.1 / 12;
    const NeighbourList nl = find_neighbours(c, sp);
    const Discretisation disc{c, nl, KernelType::CubicSpline, 1.0 / 12};
    const auto method = builtin_methods().create("mps", MethodOptions::parse({"weight=" + weight}));
    Field u(c.size());
    for (Index i = 0; i < c.size(); ++i) u[i] = std::sin(c.positions[static_cast<std::size_t>(i)].sum());
    const Eigen::MatrixXd lap = apply(method->build(disc, {.kind = OperatorKind::Laplacian}), u);
    const Eigen::MatrixXd grad = apply(method->build(disc, {.kind = OperatorKind::Gradient}), u);
    // w normalised over R^2 and its second moment, by a fine midpoint rule in r (classic: 1/r - 1).
    const ReferenceWeight pi2 = reference_weight("pi2", 2);
    auto w = [&](double s) { return weight == "classic" ? (s < 1 ? 1 / s - 1 : 0.0) : pi2.value(s); };
    double m0 = 0, m2 = 0;
    const int steps = 200000;
    for (int k = 0; k < steps; ++k) {
      const double s = (k + 0.5) / steps;
      m0 += 2 * M_PI * s * w(s) / steps;
      m2 += 2 * M_PI * s * s * s * w(s) / steps;
    }
    const double h = sp.radius, n_hat = 144, lambda = h * h * m2 / m0;
    for (Index i = 0; i < c.size(); ++i) {
      if (c.tags[static_cast<std::size_t>(i)] == Tag::Ghost) continue;
      const Vec3& x = c.positions[static_cast<std::size_t>(i)];
      double l = 0;
      Vec3 g = Vec3::Zero();
      for (Index j : nl.of(i)) {
        const Vec3 xji = c.positions[static_cast<std::size_t>(j)] - x;
        const double r = xji.norm(), wh = w(r / h) / m0 / (h * h);
        l += 4 / (n_hat * lambda) * (u[j] - u[i]) * wh;
        g += 2 / n_hat * (u[j] - u[i]) / (r * r) * wh * xji;
      }
      EXPECT_NEAR(lap(i, 0), l, 1e-6 * (std::abs(l) + 1)) << weight << " particle " << i;
      EXPECT_NEAR(grad(i, 0), g[0], 1e-6 * (g.norm() + 1)) << weight << " particle " << i;
      EXPECT_NEAR(grad(i, 1), g[1], 1e-6 * (g.norm() + 1)) << weight << " particle " << i;
    }
  }
  const PointCloud line = vertex_lattice(Domain::unit_box(1), 8);
  SearchParams sp;
  sp.radius = 0.3;
  const NeighbourList nl = find_neighbours(line, sp);
  EXPECT_THROW(builtin_methods().create("mps", {})->build({line, nl, KernelType::CubicSpline, 0.125}, {.kind = OperatorKind::Laplacian}),
               ConfigError);  // 1/r - 1 is not integrable in 1D
}

// gpm at arbitrary points: at the particles themselves it is the particle stencil (the
// interpolant includes the particle at x, (3)-(4) leave it out); off the particles it needs
// a particle within h, and names the point that has none.
TEST(GpmAt, AtParticlesEqualsTheStencils) {
  PointCloud c = cell_centred_lattice(Domain::unit_box(2), 10, false, 3);
  perturb(c, {.delta = 0.3, .seed = 2});
  SearchParams sp;
  sp.radius = 2.7 / 10;
  const NeighbourList nl = find_neighbours(c, sp);
  const Discretisation disc{c, nl, KernelType::CubicSpline, 0.1};
  for (const std::string family : {"1", "3"}) {
    const auto method = builtin_methods().create("gpm", MethodOptions::parse({"weight=" + family, "volume=uniform"}));
    Field u(c.size());
    std::vector<Real> uv(c.positions.size());
    for (Index i = 0; i < c.size(); ++i) uv[static_cast<std::size_t>(i)] = u[i] = std::cos(3 * c.positions[static_cast<std::size_t>(i)].sum());
    const auto V = gpm_volumes(disc, "uniform", family);
    std::vector<Vec3> points;
    std::vector<Real> at;
    std::vector<Index> which;
    for (Index i = 0; i < c.size(); i += 7)
      if (c.tags[static_cast<std::size_t>(i)] != Tag::Ghost) {
        points.push_back(c.positions[static_cast<std::size_t>(i)]);
        at.push_back(uv[static_cast<std::size_t>(i)]);
        which.push_back(i);
      }
    const GpmPointValues r = gpm_at_points(c, V, family, sp.radius, points, uv, at);
    const Eigen::MatrixXd val = apply(method->build(disc, {.kind = OperatorKind::Value}), u);
    const Eigen::MatrixXd grad = apply(method->build(disc, {.kind = OperatorKind::Gradient}), u);
    const Eigen::MatrixXd lap = apply(method->build(disc, {.kind = OperatorKind::Laplacian}), u);
    for (std::size_t q = 0; q < points.size(); ++q) {
      const auto e = static_cast<Eigen::Index>(q);
      const Index i = which[q];
      EXPECT_NEAR(r.value[e], val(i, 0), 1e-12) << family << " " << i;
      EXPECT_NEAR(r.gradient(e, 0), grad(i, 0), 1e-10) << family << " " << i;
      EXPECT_NEAR(r.gradient(e, 1), grad(i, 1), 1e-10) << family << " " << i;
      EXPECT_NEAR(r.laplacian[e], lap(i, 0), 1e-8 * (std::abs(lap(i, 0)) + 1)) << family << " " << i;
      EXPECT_EQ(r.neighbours[q], nl.count(i) + 1);
    }
  }
  std::vector<Real> V(c.positions.size(), 0.01), uv(c.positions.size(), 1.0);
  try {
    gpm_at_points(c, V, "2", 0.27, {Vec3(0.5, 0.5, 0), Vec3(5, 5, 0)}, uv, std::vector<Real>{1.0, 1.0});
    FAIL() << "a point far from every particle was evaluated";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("evaluation point 1 at (5, 5, 0)"), std::string::npos) << e.what();
  }
}
