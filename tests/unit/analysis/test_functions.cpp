// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

// Every catalogue function's analytic derivatives agree with the generic finite differences.
TEST(Functions, CatalogueDerivativesMatchFiniteDifferences) {
  struct Fd : ScalarFunction {
    const ScalarFunction& f;
    explicit Fd(const ScalarFunction& g) : f(g) { dim = g.dim; }
    std::string name() const override { return "fd"; }
    Real value(const Vec3& x) const override { return f.value(x); }
  };
  for (const auto& e : function_catalogue())
    for (int dim = 1; dim <= 3; ++dim) {
      const auto f = make_function(e.name, dim);
      const Fd fd(*f);
      for (const Vec3& x : {Vec3(0.3, -0.2, 0.7), Vec3(-0.9, 0.45, 0.1)}) {
        const Vec3 xx = dim == 1 ? Vec3(x[0], 0, 0) : dim == 2 ? Vec3(x[0], x[1], 0) : x;
        EXPECT_LT((f->gradient(xx) - fd.gradient(xx)).norm(), 1e-8) << e.name << " " << dim;
        EXPECT_NEAR(f->laplacian(xx), fd.laplacian(xx), 1e-6) << e.name << " " << dim;
      }
    }
}

TEST(Functions, ExpressionsParseEvaluateAndReportErrors) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  const auto u = make_expression_function("sin(pi*x)*exp(y) + z^2", 3);
  const Vec3 x(0.25, 0.5, 1.0);
  EXPECT_NEAR(u->value(x), std::sin(std::numbers::pi / 4) * std::exp(0.5) + 1, 1e-14);
  EXPECT_NEAR(u->laplacian(x), (1 - std::numbers::pi * std::numbers::pi) * std::sin(std::numbers::pi / 4) * std::exp(0.5) + 2, 1e-6);
  const auto v = make_expression_function("x*y", 2, {"y", "x"}, "0");
  EXPECT_EQ(v->gradient(Vec3(2, 3, 0)), Vec3(3, 2, 0));
  EXPECT_THROW_MSG(make_expression_function("sin(x", 2), InputError, "cannot parse expression 'sin(x'");
  EXPECT_THROW_MSG(make_expression_function("x + q", 2), InputError, "cannot parse expression 'x + q'");
  EXPECT_THROW_MSG(make_expression_function("x", 2, {"1"}), InputError, "expected 2 gradient expressions");
  EXPECT_THROW_MSG(make_function("cosine", 2), ConfigError, "unknown function 'cosine'");
  const PointCloud c = vertex_lattice(Domain::unit_box(1), 4);
  EXPECT_THROW_MSG(sample(*make_expression_function("1/x", 1), c), InputError, "is not finite (inf) at particle 0");
}

TEST(Functions, ExactDivAGrad) {
  const auto u = make_function("sin-pi", 2), a = make_function("one-plus-r2", 2);
  const Vec3 x(0.3, 0.6, 0);
  const double pi = std::numbers::pi;
  // [QW] Example 5: f = -2 pi^2 a u + 2 pi x cos(pi x) sin(pi y) + 2 pi y sin(pi x) cos(pi y)
  const double f = -2 * pi * pi * a->value(x) * u->value(x) + 2 * pi * x[0] * std::cos(pi * x[0]) * std::sin(pi * x[1]) +
                   2 * pi * x[1] * std::sin(pi * x[0]) * std::cos(pi * x[1]);
  EXPECT_NEAR(exact_operator(OperatorKind::DivAGrad, *u, a.get(), x, 0), f, 1e-12);
}

TEST(Errors, NormsAndInteriorBoundarySplit) {
  const PointCloud c = vertex_lattice(Domain::unit_box(1), 10);
  Eigen::MatrixXd e(c.size(), 1);
  for (Index i = 0; i < c.size(); ++i) e(i, 0) = (i == 1 ? -3.0 : 1.0);
  std::vector<char> rows(static_cast<std::size_t>(c.size()), 1);
  rows[0] = rows[10] = 0;
  const ErrorReport r = error_norms(e, rows, c, 0.25);
  EXPECT_EQ(r.all.count, 9);
  EXPECT_DOUBLE_EQ(r.all.linf, 3.0);
  EXPECT_EQ(r.all.worst, 1);
  EXPECT_NEAR(r.all.rms, std::sqrt((8 + 9) / 9.0), 1e-14);
  EXPECT_EQ(r.near_boundary.count, 4);  // x = 0.1, 0.2, 0.8, 0.9
  EXPECT_EQ(r.interior.count, 5);
  EXPECT_DOUBLE_EQ(r.interior.linf, 1.0);
}
