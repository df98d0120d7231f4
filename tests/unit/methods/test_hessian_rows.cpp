// SPDX-License-Identifier: BSD-3-Clause
// Hessian rows (methods/hessian_rows.hpp): exact on quartics where the support is whole, on
// cubics on a face and on quadratics in a corner; the same rows for every method through
// build_stencil; periodic boxes through the minimum-image list; a particle that cannot have a
// row is named.
#include <algorithm>
#include <numbers>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/stencil/properties.hpp>
#include <vrsph/stencil/vector_operators.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

constexpr Real kHessianPi = std::numbers::pi;

struct HessianCloud {
  PointCloud cloud;
  NeighbourList nl;
  HessianCloud(int dim, int n, Real kappa = 3) {
    cloud = vertex_lattice(Domain::unit_box(dim), n);
    perturb(cloud, {0.4, 11, false});
    SearchParams sp;
    sp.radius = kappa * cloud.spacing;
    nl = find_neighbours(cloud, sp);
  }
  Discretisation disc() const { return {cloud, nl, KernelType::CubicSpline, cloud.spacing}; }
};

// Distance from x to the box's faces: the smallest, and the second smallest over the axes (a
// particle with both below h sits in a corner's reach; in 1D an end is such a corner: a one-sided
// support of 3 dx holds about 3 neighbours, fewer than a quartic's 4 monomials).
std::pair<Real, Real> face_distances(const Vec3& x, int dim) {
  std::vector<Real> d;
  for (int k = 0; k < dim; ++k) d.push_back(std::min(x[k], 1 - x[k]));
  std::sort(d.begin(), d.end());
  return {d[0], dim > 1 ? d[1] : d[0]};
}

// Largest dimensionless residual of the rows in `rows` on the monomials of degree ≤ max_degree.
Real worst_residual(const Stencil& s, const PointCloud& c, const std::vector<char>& rows, int max_degree) {
  std::vector<Real> scale(static_cast<std::size_t>(c.size()), 3 * c.spacing);
  Real worst = 0;
  for (const MonomialResidual& m : monomial_residuals(s, c, scale, max_degree, rows)) worst = std::max(worst, m.max_residual);
  return worst;
}

}  // namespace

TEST(HessianRows, ComponentsAreTheUpperTriangle) {
  EXPECT_EQ(components(OperatorKind::Hessian, 1), 1);
  EXPECT_EQ(components(OperatorKind::Hessian, 2), 3);
  EXPECT_EQ(components(OperatorKind::Hessian, 3), 6);
  EXPECT_EQ(hessian_component(0, 1, 2), 1);
  EXPECT_EQ(hessian_component(1, 1, 2), 2);
  EXPECT_EQ(hessian_component(2, 1, 3), 4);
  for (int dim = 1; dim <= 3; ++dim)
    for (int k = 0; k < components(OperatorKind::Hessian, dim); ++k) {
      const auto [b, c] = hessian_axes(k, dim);
      EXPECT_LE(b, c);
      EXPECT_EQ(hessian_component(b, c, dim), k);
      EXPECT_EQ(hessian_component(c, b, dim), k);
    }
  EXPECT_THROW(hessian_axes(3, 2), ConfigError);
}

// Whole supports: exact on every monomial of degree ≤ 4; rows within h of one face (no ghosts;
// a half support holds about as many neighbours as a quartic has monomials) on degree ≤ 3; rows
// within h of two faces (a corner) on degree ≤ 2. Residuals are relative to 1/h².
TEST(HessianRows, ExactOnQuarticsInsideCubicsOnFacesQuadraticsInCorners) {
  for (int dim = 1; dim <= 3; ++dim) {
    const HessianCloud c(dim, dim == 3 ? 10 : dim == 2 ? 20 : 40);
    const Stencil s = hessian_rows(c.disc(), {}, "test");
    EXPECT_EQ(s.kind, OperatorKind::Hessian);
    EXPECT_EQ(s.components(), components(OperatorKind::Hessian, dim));
    const Real h = 3 * c.cloud.spacing;
    std::vector<char> inside(static_cast<std::size_t>(c.cloud.size()), 0), off_corner = inside, all(inside.size(), 1);
    for (Index i = 0; i < c.cloud.size(); ++i) {
      const auto [near, second] = face_distances(c.cloud.positions[static_cast<std::size_t>(i)], dim);
      inside[static_cast<std::size_t>(i)] = near > h;
      off_corner[static_cast<std::size_t>(i)] = second > h;
    }
    EXPECT_LT(worst_residual(s, c.cloud, inside, 4), 1e-8) << "dim " << dim;
    EXPECT_LT(worst_residual(s, c.cloud, off_corner, 3), 1e-8) << "dim " << dim;
    EXPECT_LT(worst_residual(s, c.cloud, all, 2), 1e-7) << "dim " << dim;
    // Exact on constants (difference form) and not exact on the quintic x⁵ inside: the test sees.
    EXPECT_LT(worst_residual(s, c.cloud, all, 0), 1e-10);
    std::vector<Real> scale(static_cast<std::size_t>(c.cloud.size()), h);
    Real quintic = 0;
    for (const MonomialResidual& m : monomial_residuals(s, c.cloud, scale, 5, inside))
      if (m.exponent[0] + m.exponent[1] + m.exponent[2] == 5) quintic = std::max(quintic, m.max_residual);
    EXPECT_GT(quintic, 1e-4) << "dim " << dim;
  }
}

// build_stencil gives every method these rows (no method builds them itself); Method::build
// refuses the Hessian.
TEST(HessianRows, EveryMethodGetsTheSameRows) {
  const HessianCloud c(2, 16);
  const Stencil ref = hessian_rows(c.disc(), {}, "vrsph");
  for (const std::string name : {"vrsph", "sph", "fpm"}) {
    const auto m = builtin_methods().create(name);
    EXPECT_TRUE(m->info().provides(OperatorKind::Hessian));
    EXPECT_FALSE(m->info().supports(OperatorKind::Hessian));
    const Stencil s = build_stencil(*m, c.disc(), {OperatorKind::Hessian});
    EXPECT_EQ(s.method, name);
    for (std::size_t k = 0; k < s.values.size(); ++k) EXPECT_EQ(s.values[k], ref.values[k]);
    EXPECT_THROW_MSG(m->build(c.disc(), {OperatorKind::Hessian}), ConfigError, "does not provide operator hessian");
  }
}

// On a periodic box the minimum-image list serves directly and gives the rows built on the
// periodic images (periodic_stencil); grad-div of a trigonometric field converges at third order.
TEST(HessianRows, PeriodicRowsFromTheMinimumImageList) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(2);
  spec.box.set_periodic("all");
  spec.n = 24;
  spec.delta = 0.4;
  spec.seed = 5;
  const PointCloud c = make_study_cloud(spec).cloud;
  SearchParams sp;
  sp.radius = 3 * c.spacing;
  const NeighbourList nl = find_neighbours(c, sp);
  ASSERT_FALSE(nl.shifts.empty());
  const Stencil direct = hessian_rows({c, nl, KernelType::CubicSpline, c.spacing}, {}, "vrsph");
  const auto vrsph = builtin_methods().create("vrsph");
  const Stencil images = periodic_stencil(*vrsph, c, sp, KernelType::CubicSpline, c.spacing, {OperatorKind::Hessian});
  Field u(c.size());
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& x = c.positions[static_cast<std::size_t>(i)];
    u[i] = std::sin(2 * kHessianPi * x[0]) * std::cos(2 * kHessianPi * x[1]);
  }
  const Eigen::MatrixXd a = apply(direct, u), b = apply(images, u);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-9 * a.cwiseAbs().maxCoeff());
  // u_xy = -4π² cos 2πx (-sin 2πy)
  Real worst = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& x = c.positions[static_cast<std::size_t>(i)];
    worst = std::max(worst, std::abs(a(i, 1) + 4 * kHessianPi * kHessianPi * std::cos(2 * kHessianPi * x[0]) * std::sin(2 * kHessianPi * x[1])));
  }
  EXPECT_LT(worst, 0.05 * 4 * kHessianPi * kHessianPi);
}

TEST(HessianRows, ParticlesWithoutARowAreNamed) {
  // h = 1.2 dx: a lattice particle sees its 4 axis neighbours, fewer than a quadratic's 5 monomials.
  const HessianCloud c(2, 10, 1.2);
  EXPECT_THROW_MSG(hessian_rows(c.disc(), {}, "test"), InputError, "a row exact on quadratics needs at least 5");
  const HessianCloud d(2, 10);
  EXPECT_THROW_MSG(hessian_rows(d.disc(), {}, "test", 5), ConfigError, "must be 2, 3 or 4");
  // Particles on one line: no second derivative across it.
  PointCloud line;
  line.dim = 2;
  line.spacing = 0.1;
  line.domain = Domain::unit_box(2);
  for (int i = 0; i <= 10; ++i) line.add(Vec3(0.1 * i, 0.5, 0), Tag::Interior);
  SearchParams sp;
  sp.radius = 0.75;  // 7 neighbours or more, all on the line
  const NeighbourList nl = find_neighbours(line, sp);
  EXPECT_THROW_MSG(hessian_rows({line, nl, KernelType::CubicSpline, 0.1}, {}, "test"), InputError,
                   "do not determine a quadratic");
}

// grad div U from the Hessian rows equals Σ_c H_bc U_c; the composed form G (div U) is kept as
// grad-div-composed.
TEST(HessianRows, GradDivFromTheHessian) {
  const HessianCloud c(2, 16);
  const Stencil H = hessian_rows(c.disc(), {}, "test");
  Eigen::MatrixXd U(c.cloud.size(), 2);
  for (Index i = 0; i < c.cloud.size(); ++i) {
    const Vec3& x = c.cloud.positions[static_cast<std::size_t>(i)];
    U(i, 0) = x[0] * x[0] - x[1] * x[1];  // div U = 2x + x = 3x: grad (3, 0) (quadratics: corners too)
    U(i, 1) = x[0] * x[1];
  }
  const Eigen::MatrixXd g = apply_vector(VectorOperator::GradDiv, H, U);
  for (Index i = 0; i < c.cloud.size(); ++i) {
    EXPECT_NEAR(g(i, 0), 3, 1e-7);
    EXPECT_NEAR(g(i, 1), 0, 1e-7);
  }
  EXPECT_EQ(base_operator(VectorOperator::GradDiv), OperatorKind::Hessian);
  EXPECT_EQ(base_operator(VectorOperator::GradDivComposed), OperatorKind::Gradient);
  EXPECT_EQ(parse_vector_operator("grad-div-composed"), VectorOperator::GradDivComposed);
  const auto fpm = builtin_methods().create("fpm");
  const Stencil G = fpm->build(c.disc(), {OperatorKind::Gradient});
  EXPECT_THROW_MSG(apply_vector(VectorOperator::GradDiv, G, U), InputError, "made from a hessian stencil");
}
