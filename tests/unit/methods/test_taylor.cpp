// SPDX-License-Identifier: BSD-3-Clause
// Taylor-corrected and [AAR] methods: polynomial exactness they must have, the
// singular-system policy, condition numbers, and the nested D·D construction.
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct Cloud {
  PointCloud cloud;
  NeighbourList nl;
  KernelType kernel;
  Cloud(int dim, double delta, double kappa, KernelType k = KernelType::CubicSpline, int n = 0) : kernel(k) {
    cloud = vertex_lattice(Domain::unit_box(dim), n > 0 ? n : dim == 3 ? 7 : dim == 2 ? 14 : 30);
    if (delta > 0) perturb(cloud, {delta, 5, false});
    SearchParams sp;
    sp.radius = kappa * cloud.spacing;
    nl = find_neighbours(cloud, sp);
  }
  Stencil build(const std::string& m, OperatorKind k, const MethodOptions& o = {}, const Field* a = nullptr) const {
    return builtin_methods().create(m, o)->build({cloud, nl, kernel, cloud.spacing}, {k, a});
  }
  Field eval(auto&& f) const {
    Field u(cloud.size());
    for (Index i = 0; i < u.size(); ++i) u[i] = f(cloud.positions[static_cast<std::size_t>(i)]);
    return u;
  }
};
}  // namespace

TEST(TaylorMethods, GradientExactForLinearFieldsOnPerturbedClouds) {
  for (int dim = 1; dim <= 3; ++dim) {
    const Cloud c(dim, 0.4, 3.2);
    const Field u = c.eval([](const Vec3& x) { return 1 + 2 * x[0] - 3 * x[1] + 0.5 * x[2]; });
    const Vec3 g(2, -3, 0.5);
    for (const auto* m : {"fpm", "kgf", "cspm", "chen-beraun"}) {
      const Eigen::MatrixXd gu = apply(c.build(m, OperatorKind::Gradient), u);
      for (int k = 0; k < dim; ++k) EXPECT_LT((gu.col(k).array() - g[k]).abs().maxCoeff(), 1e-9) << m << " dim " << dim;
    }
  }
}

TEST(TaylorMethods, SecondOrderFitsExactForQuadratics) {
  for (int dim = 1; dim <= 3; ++dim) {
    const Cloud c(dim, 0.4, 3.2);
    const Field u = c.eval([](const Vec3& x) { return 1 + x[0] + x[0] * x[0] - 2 * x[0] * x[1] + 3 * x[1] * x[1] + x[2] * x[2]; });
    const double lap = 2 + (dim >= 2 ? 6 : 0) + (dim >= 3 ? 2 : 0);
    for (const auto* m : {"fpm", "kgf"}) {
      const Field l = apply_component(c.build(m, OperatorKind::Laplacian), u, 0);
      EXPECT_LT((l.array() - lap).abs().maxCoeff(), 1e-7) << m << " dim " << dim;
    }
  }
}

TEST(TaylorMethods, AarFpmVariantsExactForQuadraticsIn1D) {
  const Cloud c(1, 0.25, 6, KernelType::Gaussian, 40);
  const Field u = c.eval([](const Vec3& x) { return 2 - x[0] + 3 * x[0] * x[0]; });
  for (const auto* m : {"mfpm", "fpm2o"}) {
    const Field d = apply_component(c.build(m, OperatorKind::Dx), u, 0);
    const Field d2 = apply_component(c.build(m, OperatorKind::Laplacian), u, 0);
    for (Index i = 0; i < u.size(); ++i) {
      EXPECT_NEAR(d[i], -1 + 6 * c.cloud.positions[static_cast<std::size_t>(i)][0], 1e-7) << m << " particle " << i;
      EXPECT_NEAR(d2[i], 6, 1e-6) << m << " particle " << i;
    }
  }
}

TEST(TaylorMethods, ConditionNumbersReportedAndModerateOnLattices) {
  const Cloud c(2, 0.3, 3);
  for (const auto* m : {"fpm", "kgf", "cspm", "rkpm2"}) {
    const Stencil s = c.build(m, OperatorKind::Laplacian);
    ASSERT_EQ(static_cast<Index>(s.condition.size()), c.cloud.size()) << m;
    for (Real k : s.condition) {
      EXPECT_GE(k, 1) << m;
      EXPECT_LT(k, 1e8) << m;
    }
  }
}

TEST(TaylorMethods, SingularLocalSystemIsAnErrorNamingTheParticleOrAWarning) {
  // Two particles in 2D: each sees one neighbour, the 2x2 gradient system is singular.
  PointCloud cloud;
  cloud.dim = 2;
  cloud.add(Vec3(0, 0, 0), Tag::Interior);
  cloud.add(Vec3(0.1, 0, 0), Tag::Interior);
  cloud.spacing = 0.1;
  SearchParams sp;
  sp.radius = 0.3;
  const NeighbourList nl = find_neighbours(cloud, sp);
  for (const auto* m : {"fpm", "kgf", "cspm", "rkpm1"}) {
    const auto method = builtin_methods().create(m);
    EXPECT_THROW_MSG((void)method->build({cloud, nl, KernelType::CubicSpline, 0.1}, {OperatorKind::Gradient}),
                     NumericalError, "particle 0");
    MethodOptions warn;
    warn.set("on_singular", "warn");
    const Stencil s = builtin_methods().create(m, warn)->build({cloud, nl, KernelType::CubicSpline, 0.1}, {OperatorKind::Gradient});
    ASSERT_EQ(s.local_failure.size(), 2u) << m;
    EXPECT_TRUE(s.local_failure[0] && s.local_failure[1]) << m;
    for (const auto& v : s.values)
      for (Real x : v) EXPECT_EQ(x, 0) << m << ": a failed row must be empty, never NaN";
  }
}

TEST(TaylorMethods, FpmQwVariantOnlyIn1D) {
  const Cloud c(2, 0, 3);
  MethodOptions o;
  o.set("variant", "qw");
  EXPECT_THROW_MSG((void)c.build("fpm", OperatorKind::Laplacian, o), ConfigError, "1D only");
  EXPECT_THROW_MSG((void)c.build("mfpm", OperatorKind::Laplacian), ConfigError, "1D only");
}

TEST(NestedMethods, LaplacianIsTheGradientAppliedTwice) {
  for (int dim = 1; dim <= 2; ++dim) {
    const Cloud c(dim, 0.3, 3);
    const Field u = c.eval([](const Vec3& x) { return std::sin(3 * x[0]) + x[1] * x[1] * x[0]; });
    Field a = c.eval([](const Vec3& x) { return 1 + x[0] * x[0]; });
    for (const auto* m : {"aar-sph", "rkpm1", "rkpm2"}) {
      const Stencil g = c.build(m, OperatorKind::Gradient);
      const Eigen::MatrixXd gu = apply(g, u);
      Field twice = Field::Zero(u.size()), flux = Field::Zero(u.size());
      for (int k = 0; k < dim; ++k) {
        twice += apply_component(g, Field(gu.col(k)), k);
        flux += apply_component(g, Field(a.cwiseProduct(gu.col(k))), k);
      }
      const Field lap = apply_component(c.build(m, OperatorKind::Laplacian), u, 0);
      const Field div = apply_component(c.build(m, OperatorKind::DivAGrad, {}, &a), u, 0);
      EXPECT_LT((lap - twice).cwiseAbs().maxCoeff(), 1e-9 * twice.cwiseAbs().maxCoeff()) << m << " dim " << dim;
      EXPECT_LT((div - flux).cwiseAbs().maxCoeff(), 1e-9 * flux.cwiseAbs().maxCoeff()) << m << " dim " << dim;
    }
  }
}

TEST(RegisteredMethods, EveryMethodExactOnConstants) {
  for (const auto& info : builtin_methods().list()) {
    const int dim = info.name == "mfpm" || info.name == "fpm2o" ? 1 : 2;
    const Cloud c(dim, 0.3, dim == 1 ? 6 : 3, dim == 1 ? KernelType::Gaussian : KernelType::CubicSpline);
    const Field one = Field::Ones(c.cloud.size());
    Field a = Field::Constant(c.cloud.size(), 2.0);
    for (auto k : {OperatorKind::Gradient, OperatorKind::Laplacian, OperatorKind::DivAGrad}) {
      if (!info.supports(k)) continue;
      const Eigen::MatrixXd r = apply(c.build(info.name, k, {}, &a), one);
      EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-8) << info.name << " " << to_string(k);
    }
  }
}
