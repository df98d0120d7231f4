// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/sph/sph.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct Lattice {
  PointCloud cloud;
  NeighbourList nl;
  explicit Lattice(int dim, double delta = 0, double kappa = 3) {
    cloud = cell_centred_lattice(Domain::symmetric_box(dim, 1), dim == 3 ? 8 : 16, false, static_cast<int>(kappa) + 1);
    if (delta > 0) perturb(cloud, {delta, 3, false});
    SearchParams sp;
    sp.radius = kappa * cloud.spacing;
    nl = find_neighbours(cloud, sp);
  }
  Stencil build(OperatorKind k, const MethodOptions& o = {}, const Field* a = nullptr) const {
    return builtin_methods().create("sph", o)->build({cloud, nl, KernelType::CubicSpline, cloud.spacing}, {k, a});
  }
  Field eval(auto&& f) const {
    Field u(cloud.size());
    for (Index i = 0; i < u.size(); ++i) u[i] = f(cloud.positions[static_cast<std::size_t>(i)]);
    return u;
  }
};
}  // namespace

TEST(Sph, ExactOnConstantsForEveryDerivativeOperator) {
  for (int dim = 1; dim <= 3; ++dim) {
    const Lattice l(dim, 0.5);
    const Field one = Field::Ones(l.cloud.size());
    Field a = Field::Constant(l.cloud.size(), 2.0);
    for (auto k : {OperatorKind::Gradient, OperatorKind::Laplacian, OperatorKind::DivAGrad, OperatorKind::Dx}) {
      const Stencil s = l.build(k, {}, &a);
      EXPECT_LT(apply(s, one).cwiseAbs().maxCoeff(), 1e-9) << dim << "D " << to_string(k);
    }
  }
}

// Sign convention (METHODS §1.4): the gradient of c.x is +c, not -c, and the Brookshaw
// weights are non-negative, so the Laplacian diagonal is negative.
TEST(Sph, SignConventions) {
  const Lattice l(2);
  const Stencil g = l.build(OperatorKind::Gradient);
  const Field u = l.eval([](const Vec3& x) { return 2 * x[0] - 3 * x[1]; });
  const Eigen::MatrixXd gu = apply(g, u);
  for (Index i = 0; i < l.cloud.size(); ++i) {
    if (l.cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    EXPECT_NEAR(gu(i, 0), 2.0, 0.02);
    EXPECT_NEAR(gu(i, 1), -3.0, 0.03);
  }
  const Stencil lap = l.build(OperatorKind::Laplacian);
  for (Index i = 0; i < l.cloud.size(); ++i) {
    if (l.cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    for (Index k = lap.row_begin(i); k < lap.row_end(i); ++k) {
      if (lap.col[static_cast<std::size_t>(k)] == i) EXPECT_LT(lap.values[0][static_cast<std::size_t>(k)], 0);
      else EXPECT_GE(lap.values[0][static_cast<std::size_t>(k)], 0);
    }
  }
}

TEST(Sph, MorrisEqualsBrookshawForConstantCoefficient) {
  const Lattice l(2, 0.4);
  Field a = Field::Constant(l.cloud.size(), 0.5);  // (a_i + a_j)/2 = 0.5 -> Morris = 0.5 * Brookshaw
  const Stencil m = l.build(OperatorKind::DivAGrad, {}, &a), b = l.build(OperatorKind::Laplacian);
  for (std::size_t k = 0; k < m.values[0].size(); ++k) EXPECT_NEAR(m.values[0][k], 0.5 * b.values[0][k], 1e-12 * std::abs(b.values[0][k]) + 1e-300);
}

TEST(Sph, InterpolationAndShepardVolumes) {
  const Lattice l(2);
  const Stencil v = l.build(OperatorKind::Value);
  const Field one = Field::Ones(l.cloud.size());
  const Field r = apply_component(v, one, 0);
  const Stencil vs = l.build(OperatorKind::Value, MethodOptions::parse({"volume=shepard"}));
  const Field rs = apply_component(vs, one, 0);
  for (Index i = 0; i < l.cloud.size(); ++i) {
    if (l.cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    EXPECT_NEAR(r[i], 1.0, 5e-3);  // lattice sum of W at h = 3 dx: 1.0034
    EXPECT_NEAR(rs[i], 1.0, 5e-3);
  }
  const auto vol = sph_volumes({l.cloud, l.nl, KernelType::CubicSpline, l.cloud.spacing}, SphVolume::Shepard);
  std::size_t centre = 0;
  for (std::size_t i = 0; i < vol.size(); ++i)
    if (l.cloud.positions[i].norm() < l.cloud.positions[centre].norm()) centre = i;
  EXPECT_NEAR(vol[centre], l.cloud.spacing * l.cloud.spacing, 5e-3 * l.cloud.spacing * l.cloud.spacing);
}

TEST(Sph, GhostRowsAreEmpty) {
  const Lattice l(1);
  const Stencil lap = l.build(OperatorKind::Laplacian);
  for (Index i = 0; i < l.cloud.size(); ++i)
    if (l.cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost) {
      for (Index k = lap.row_begin(i); k < lap.row_end(i); ++k) EXPECT_EQ(lap.values[0][static_cast<std::size_t>(k)], 0.0);
    }
}
