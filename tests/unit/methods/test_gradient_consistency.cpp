// SPDX-License-Identifier: BSD-3-Clause
// Gradient rows raised to exactness on cubics (methods/gradient_consistency.hpp): VRSPH's default
// and FPM/KGF gradient_order=3 are [QW]'s / the quadratic fit's rows plus that correction, exact on
// every cubic at each raised row; rows that cannot be raised keep their weights; bad requests are
// refused.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/gradient_consistency.hpp>
#include <vrsph/methods/monomials.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

struct PerturbedCloud {
  PointCloud cloud;
  NeighbourList nl;
  PerturbedCloud(int dim, double kappa = 3.2) {
    cloud = vertex_lattice(Domain::unit_box(dim), dim == 3 ? 8 : dim == 2 ? 16 : 40);
    perturb(cloud, {0.4, 7, false});
    SearchParams sp;
    sp.radius = kappa * cloud.spacing;
    nl = find_neighbours(cloud, sp);
  }
  Discretisation disc() const { return {cloud, nl, KernelType::CubicSpline, cloud.spacing}; }
  Stencil build(const std::string& method, OperatorKind kind, const MethodOptions& o) const {
    return builtin_methods().create(method, o)->build(disc(), {kind});
  }
};

// A full cubic in x, y, z and its gradient.
Real cubic(const Vec3& x) {
  return 1 - 2 * x[0] + x[1] + 0.5 * x[2] + 3 * x[0] * x[0] - x[0] * x[1] + 2 * x[1] * x[2] - x[2] * x[2] +
         4 * x[0] * x[0] * x[0] - 2 * x[0] * x[0] * x[1] + 1.5 * x[0] * x[1] * x[2] - 3 * x[1] * x[1] * x[1] +
         x[1] * x[2] * x[2] + 2 * x[2] * x[2] * x[2];
}
Vec3 cubic_gradient(const Vec3& x) {
  return {-2 + 6 * x[0] - x[1] + 12 * x[0] * x[0] - 4 * x[0] * x[1] + 1.5 * x[1] * x[2],
          1 - x[0] + 2 * x[2] - 2 * x[0] * x[0] + 1.5 * x[0] * x[2] - 9 * x[1] * x[1] + x[2] * x[2],
          0.5 + 2 * x[1] - 2 * x[2] + 1.5 * x[0] * x[1] + 2 * x[1] * x[2] + 6 * x[2] * x[2]};
}

Field sample(const PointCloud& c, Real (*f)(const Vec3&)) {
  Field u(c.size());
  for (Index i = 0; i < c.size(); ++i) u[i] = f(c.positions[static_cast<std::size_t>(i)]);
  return u;
}

// Largest error of the gradient stencil s on the cubic over the rows not in `skip`, relative to
// the largest exact derivative.
Real worst_cubic_error(const PointCloud& c, const Stencil& s, const std::vector<Index>& skip) {
  const Eigen::MatrixXd g = apply(s, sample(c, cubic));
  Real worst = 0;
  for (Index i = 0; i < c.size(); ++i) {
    if (std::binary_search(skip.begin(), skip.end(), i)) continue;
    const Vec3 exact = cubic_gradient(c.positions[static_cast<std::size_t>(i)]);
    for (int k = 0; k < c.dim; ++k) worst = std::max(worst, std::abs(g(i, k) - exact[k]) / 30.0);
  }
  return worst;
}

}  // namespace

TEST(GradientConsistency, VrsphDefaultIsQwRowsRaisedAndExactOnCubics) {
  for (int dim = 1; dim <= 3; ++dim) {
    const PerturbedCloud c(dim);
    const Stencil qw = c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2"}));
    Stencil raised = qw;
    const GradientConsistencyReport report = raise_to_cubic_exactness(c.disc(), {OperatorKind::Gradient}, raised);
    // The method's default is exactly this correction of [QW]'s rows.
    const Stencil def = c.build("vrsph", OperatorKind::Gradient, {});
    for (int k = 0; k < dim; ++k) EXPECT_EQ(def.values[static_cast<std::size_t>(k)], raised.values[static_cast<std::size_t>(k)]);
    // Every row at least a support from the faces is raised; near the faces (no ghost layers here)
    // some one-sided rows are worse conditioned than 1e4 and keep [QW]'s row (measured: 16 of 289
    // in 2D, 148 of 729 in 3D). Each raised row is exact on the cubic.
    EXPECT_EQ(report.raised + static_cast<Index>(report.kept.size()), c.cloud.size()) << "dim " << dim;
    EXPECT_LE(static_cast<Index>(report.kept.size()), c.cloud.size() / 4) << "dim " << dim;
    const Real h = 3.2 * c.cloud.spacing;
    for (Index i : report.kept) {
      const Vec3& x = c.cloud.positions[static_cast<std::size_t>(i)];
      bool near_face = false;
      for (int k = 0; k < dim; ++k) near_face = near_face || x[k] < h || x[k] > 1 - h;
      EXPECT_TRUE(near_face) << "dim " << dim << ": interior row " << i << " kept";
    }
    EXPECT_LT(worst_cubic_error(c.cloud, def, report.kept), 1e-8) << "dim " << dim;
    // [QW]'s rows are not (their O(h^2) error is the cubic's third derivatives).
    EXPECT_GT(worst_cubic_error(c.cloud, qw, {}), 1e-3) << "dim " << dim;
    // A raised row meets its moment conditions: its NNLS residual is cleared.
    for (Index i = 0; i < c.cloud.size(); ++i) {
      if (!std::binary_search(report.kept.begin(), report.kept.end(), i)) {
        EXPECT_EQ(def.residual[static_cast<std::size_t>(i)], 0);
      }
    }
    // A kept row is the row it was.
    for (Index i : report.kept)
      for (Index p = qw.row_begin(i); p < qw.row_end(i); ++p)
        EXPECT_EQ(def.values[0][static_cast<std::size_t>(p)], qw.values[0][static_cast<std::size_t>(p)]);
  }
}

TEST(GradientConsistency, FpmAndKgfOrderThreeAndSingleDerivatives) {
  const PerturbedCloud c(2);
  for (const char* m : {"fpm", "kgf"}) {
    const Stencil g = c.build(m, OperatorKind::Gradient, MethodOptions::parse({"gradient_order=3"}));
    Stencil again = c.build(m, OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2"}));
    const auto report = raise_to_cubic_exactness(c.disc(), {OperatorKind::Gradient}, again);
    EXPECT_LT(worst_cubic_error(c.cloud, g, report.kept), 1e-8) << m;
  }
  // Dy alone: the gradient's second component (to rounding: Dy's NNLS runs on its own request).
  const Stencil dy = c.build("vrsph", OperatorKind::Dy, {});
  const Stencil grad = c.build("vrsph", OperatorKind::Gradient, {});
  ASSERT_EQ(dy.values[0].size(), grad.values[1].size());
  for (std::size_t p = 0; p < dy.values[0].size(); ++p) EXPECT_NEAR(dy.values[0][p], grad.values[1][p], 1e-9) << p;
}

TEST(GradientConsistency, RowsThatCannotBeRaisedKeepTheirWeights) {
  const PerturbedCloud c(2);
  const Stencil qw = c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2"}));
  Stencil s = qw;
  // No system has condition number below 1: every row is kept, bit for bit.
  const auto report = raise_to_cubic_exactness(c.disc(), {OperatorKind::Gradient}, s, 1.0);
  EXPECT_EQ(report.raised, 0);
  EXPECT_EQ(static_cast<Index>(report.kept.size()), c.cloud.size());
  EXPECT_EQ(s.values, qw.values);
  // Too few neighbours for the 9 monomials of a 2D cubic (support 1.2 dx: about 4).
  const PerturbedCloud sparse(2, 1.2);
  Stencil t = sparse.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2", "nnls_max_iterations=100"}));
  const Stencil before = t;
  const auto few = raise_to_cubic_exactness(sparse.disc(), {OperatorKind::Gradient}, t);
  EXPECT_EQ(few.raised, 0);
  EXPECT_EQ(t.values, before.values);
}

TEST(GradientConsistency, BadRequestsAreRefused) {
  const PerturbedCloud c(2);
  EXPECT_THROW_MSG(c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"profile=qw", "gradient_order=3"})),
                   ConfigError, "contradicts profile=qw");
  EXPECT_THROW(c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=4"})), ConfigError);
  EXPECT_THROW(c.build("fpm", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=0"})), ConfigError);
  Stencil lap = c.build("vrsph", OperatorKind::Laplacian, {});
  EXPECT_THROW_MSG(raise_to_cubic_exactness(c.disc(), {OperatorKind::Laplacian}, lap), ConfigError,
                   "first-derivative stencils");
  // profile=qw alone pins [QW]'s gradient rows.
  EXPECT_EQ(c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"profile=qw"})).values,
            c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2"})).values);
}

namespace {

// Each row's equilibrated 1-norm condition number computed from scratch (Eigen's dense inverse):
// A = Σ_k W_k p(q_k) p(q_k)^T over the neighbours, q_k = (x_k - x_i) / h, p the monomials of degree
// 1 ... 3, B = D A D with unit diagonal; cond = ||B||_1 ||B^-1||_1 (infinite when B is singular).
std::vector<Real> cubic_conditions(const PerturbedCloud& c) {
  const auto exps = monomial_exponents(c.cloud.dim, 3);
  const auto m = static_cast<Eigen::Index>(exps.size());
  std::vector<Real> out;
  for (Index i = 0; i < c.cloud.size(); ++i) {
    const Real h = c.nl.radius(i);
    const Kernel ker(KernelType::CubicSpline, c.cloud.dim, h);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m);
    const auto nbr = c.nl.of(i);
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3 q = (c.cloud.positions[static_cast<std::size_t>(nbr[k])] - c.cloud.positions[static_cast<std::size_t>(i)]) / h;
      Eigen::VectorXd p(m);
      for (Eigen::Index a = 0; a < m; ++a) {
        const auto& e = exps[static_cast<std::size_t>(a)];
        p[a] = std::pow(q[0], e[0]) * std::pow(q[1], e[1]) * std::pow(q[2], e[2]);
      }
      A += ker.W(c.nl.distances_of(i)[k]) / ker.W(0) * p * p.transpose();
    }
    const Eigen::VectorXd d = A.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd B = d.asDiagonal() * A * d.asDiagonal();
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
    out.push_back(lu.isInvertible() ? B.cwiseAbs().colwise().sum().maxCoeff() * lu.inverse().cwiseAbs().colwise().sum().maxCoeff()
                                    : std::numeric_limits<Real>::infinity());
  }
  return out;
}

}  // namespace

// The conditioning test bounds ||B^-1||_1 from its Cholesky factor first and forms B^-1 only for
// the rows whose bound fails: the rows kept must be exactly those whose condition number exceeds
// the limit, whatever the limit (here quantiles of the rows' own numbers, so that both kinds occur,
// near the faces and inside).
TEST(GradientConsistency, KeptRowsAreExactlyThoseWorseConditionedThanTheLimit) {
  for (int dim = 2; dim <= 3; ++dim) {
    const PerturbedCloud c(dim);
    const std::vector<Real> cond = cubic_conditions(c);
    std::vector<Real> sorted = cond;
    std::sort(sorted.begin(), sorted.end());
    const Stencil qw = c.build("vrsph", OperatorKind::Gradient, MethodOptions::parse({"gradient_order=2"}));
    for (const double quantile : {0.1, 0.5, 0.9, 0.97}) {
      const auto at = static_cast<std::size_t>(quantile * static_cast<double>(sorted.size()));
      const Real limit = std::sqrt(sorted[at] * sorted[at + 1]);  // between two rows' numbers
      if (!(sorted[at + 1] > sorted[at] * (1 + 1e-6))) continue;   // no clean gap at this quantile
      Stencil s = qw;
      const auto report = raise_to_cubic_exactness(c.disc(), {OperatorKind::Gradient}, s, limit);
      std::vector<Index> expected;
      for (Index i = 0; i < c.cloud.size(); ++i)
        if (!(cond[static_cast<std::size_t>(i)] <= limit)) expected.push_back(i);
      EXPECT_EQ(report.kept, expected) << "dim " << dim << ", limit " << limit;
      EXPECT_GT(report.raised, 0) << "dim " << dim;
      EXPECT_FALSE(report.kept.empty()) << "dim " << dim;
    }
  }
}
