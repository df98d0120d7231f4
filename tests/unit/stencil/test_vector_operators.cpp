// SPDX-License-Identifier: BSD-3-Clause
// Divergence, curl and vector Laplacian from a method's gradient / Laplacian rows: exact on
// the fields the rows are exact on (linear for the gradient, quadratic for VRSPH's and FPM's
// Laplacian) at interior particles, and the shapes checked.
#include <cmath>
#include <vector>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/vector_operators.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct Built {
  PointCloud cloud;
  Stencil gradient, laplacian;
};

Built build(const char* method, int dim) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(dim);
  spec.n = dim == 2 ? 16 : 8;
  spec.layout = Layout::CellCentred;
  spec.ghost_width = 4.0 / spec.n;  // full supports at every interior particle
  Built b{make_study_cloud(spec).cloud, {}, {}};
  SearchParams sp;
  sp.radius = 3 * b.cloud.spacing;
  const NeighbourList nl = find_neighbours(b.cloud, sp);
  const auto m = builtin_methods().create(method);
  b.gradient = m->build({b.cloud, nl, KernelType::CubicSpline, b.cloud.spacing}, StencilRequest{OperatorKind::Gradient});
  b.laplacian = m->build({b.cloud, nl, KernelType::CubicSpline, b.cloud.spacing}, StencilRequest{OperatorKind::Laplacian});
  return b;
}
}  // namespace

TEST(VectorOperators, ExactOnLinearAndQuadraticFields) {
  for (const char* method : {"vrsph", "fpm"})
    for (int dim : {2, 3}) {
      const Built b = build(method, dim);
      const Index n = b.cloud.size();
      Eigen::MatrixXd lin(n, dim), quad(n, dim);
      for (Index i = 0; i < n; ++i) {
        const Vec3& x = b.cloud.positions[static_cast<std::size_t>(i)];
        lin.row(i) << 2 * x[0] + 3 * x[1], -x[0] + 5 * x[1] + x[2], Eigen::RowVectorXd::Constant(dim - 2, 4 * x[0] - 2 * x[2]);
        quad.row(i) << x[0] * x[0] + x[1] * x[1], x[0] * x[1], Eigen::RowVectorXd::Constant(dim - 2, x[2] * x[2]);
      }
      const Eigen::MatrixXd div = apply_vector(VectorOperator::Divergence, b.gradient, lin);
      const Eigen::MatrixXd curl = apply_vector(VectorOperator::Curl, b.gradient, lin);
      const Eigen::MatrixXd lap = apply_vector(VectorOperator::VectorLaplacian, b.laplacian, quad);
      ASSERT_EQ(curl.cols(), dim == 2 ? 1 : 3);
      // div = 2 + 5 (3D: - 2); curl 2D = -1 - 3; 3D = (0 - 1, 0 - 4, -1 - 3); lap = (4, 0 (, 2)).
      const Eigen::RowVector3d curl3(-1, -4, -4);
      for (Index i = 0; i < n; ++i) {
        if (b.cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
        EXPECT_NEAR(div(i, 0), dim == 2 ? 7 : 5, 1e-8) << method << " " << dim << "D particle " << i;
        if (dim == 2) {
          EXPECT_NEAR(curl(i, 0), -4, 1e-8) << method << " particle " << i;
        } else {
          EXPECT_LT((curl.row(i) - curl3).norm(), 1e-8) << method << " 3D particle " << i;
        }
        EXPECT_NEAR(lap(i, 0), 4, 1e-7) << method << " " << dim << "D particle " << i;
        EXPECT_NEAR(lap(i, 1), 0, 1e-7) << method << " " << dim << "D particle " << i;
        if (dim == 3) {
          EXPECT_NEAR(lap(i, 2), 2, 1e-7) << method << " particle " << i;
        }
      }
    }
}

TEST(VectorOperators, ShapesAndKindsAreChecked) {
  const Built b = build("fpm", 2);
  EXPECT_THROW_MSG(apply_vector(VectorOperator::Divergence, b.laplacian, Eigen::MatrixXd::Zero(b.cloud.size(), 2)),
                   InputError, "divergence is made from a gradient stencil");
  EXPECT_THROW_MSG(apply_vector(VectorOperator::Divergence, b.gradient, Eigen::MatrixXd::Zero(b.cloud.size(), 3)),
                   InputError, "one column per component");
  EXPECT_THROW_MSG(output_components(VectorOperator::Curl, 1), ConfigError, "the curl needs 2 or 3 dimensions");
  EXPECT_EQ(parse_vector_operator("vector-laplacian"), VectorOperator::VectorLaplacian);
  EXPECT_FALSE(parse_vector_operator("laplacian").has_value());
}

// The divergence and the curl read only the derivatives they need in one pass: the same values,
// bit for bit, as the gradient applied to every component and the derivatives combined.
TEST(VectorOperators, DivergenceAndCurlEqualTheCombinedGradientBitForBit) {
  for (int dim : {2, 3}) {
    const Built b = build("vrsph", dim);
    const Index n = b.cloud.size();
    Eigen::MatrixXd U(n, dim);
    for (Index i = 0; i < n; ++i) {
      const Vec3& x = b.cloud.positions[static_cast<std::size_t>(i)];
      for (int c = 0; c < dim; ++c) U(i, c) = std::sin(3 * x[c] + c) * std::exp(x[(c + 1) % dim]);
    }
    // d[c](:, b) = G_b U_c
    std::vector<Eigen::MatrixXd> d;
    for (int c = 0; c < dim; ++c) d.push_back(apply(b.gradient, Field(U.col(c))));
    const Eigen::MatrixXd div = apply_vector(VectorOperator::Divergence, b.gradient, U);
    const Eigen::MatrixXd curl = apply_vector(VectorOperator::Curl, b.gradient, U);
    for (Index i = 0; i < n; ++i) {
      Real sum = 0;
      for (int c = 0; c < dim; ++c) sum += d[static_cast<std::size_t>(c)](i, c);
      ASSERT_EQ(div(i, 0), sum) << dim << "D particle " << i;
      if (dim == 2) {
        ASSERT_EQ(curl(i, 0), d[1](i, 0) - d[0](i, 1)) << "particle " << i;
      } else {
        ASSERT_EQ(curl(i, 0), d[2](i, 1) - d[1](i, 2)) << "particle " << i;
        ASSERT_EQ(curl(i, 1), d[0](i, 2) - d[2](i, 0)) << "particle " << i;
        ASSERT_EQ(curl(i, 2), d[1](i, 0) - d[0](i, 1)) << "particle " << i;
      }
    }
  }
}
