// SPDX-License-Identifier: BSD-3-Clause
// The one-call BVP API on a user's own cloud (no box, no generator): an L-shaped
// lattice built from arrays, Dirichlet, mixed and pure-Neumann data.
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include <vrsph/problem/from_expressions.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// [0,1]^2 minus (1/2,1]^2 on a lattice of spacing 1/n; boundary particles Dirichlet.
PointCloud l_shape(int n) {
  PointCloud c;
  c.dim = 2;
  const Real dx = 1.0 / n;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const Real x = i * dx, y = j * dx;
      if (2 * i > n && 2 * j > n) continue;
      const bool boundary = i == 0 || j == 0 || i == n || j == n || (2 * i == n && 2 * j >= n) || (2 * j == n && 2 * i >= n);
      c.add(Vec3(x, y, 0), boundary ? Tag::Dirichlet : Tag::Interior);
    }
  return c;
}
Real quadratic(const Vec3& x) { return 1 + x[0] + 2 * x[1] + x[0] * x[0] + 0.5 * x[1] * x[1]; }  // Δ = 3
}  // namespace

TEST(SolveBvp, QuadraticExactOnAnLShapedCloudFromArrays) {
  for (const char* method : {"vrsph", "fpm"}) {
    BoundaryValueProblem p;
    p.cloud = l_shape(24);
    const Index n = p.cloud.size();
    p.f = Field::Constant(n, 3.0);
    p.g.resize(n);
    for (Index i = 0; i < n; ++i) p.g[i] = quadratic(p.cloud.positions[static_cast<std::size_t>(i)]);
    BvpSolveOptions o;
    o.method = method;
    const BvpSolution s = solve(p, o);
    EXPECT_EQ(s.unknowns, p.cloud.count(Tag::Interior));
    EXPECT_NEAR(s.spacing * 24, 1.0, 0.03) << "robust spacing estimate of a lattice";
    EXPECT_EQ(s.infeasible, 0) << method;
    EXPECT_LT((s.u - p.g).cwiseAbs().maxCoeff(), 1e-9) << method;
    if (std::string(method) == "vrsph") {
      EXPECT_TRUE(s.m_matrix) << s.m_matrix_summary;
    }
  }
}

TEST(SolveBvp, MasksAndMixedDirichletNeumann) {
  PointCloud c = l_shape(8);
  const std::vector<char> unknown = unknown_mask(c), dirichlet = tag_mask(c, {Tag::Dirichlet});
  EXPECT_EQ(std::count(unknown.begin(), unknown.end(), 1), c.count(Tag::Interior));
  EXPECT_EQ(std::count(dirichlet.begin(), dirichlet.end(), 1), c.count(Tag::Dirichlet));
  // The faces x = 0 and y = 0 (without the corner) become Neumann: u = x + y, linear, so
  // FPM's first-order flux rows are exact too.
  BoundaryValueProblem p;
  p.cloud = c;
  p.cloud.normals.assign(static_cast<std::size_t>(c.size()), Vec3::Zero());
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    if (c.tags[si] != Tag::Dirichlet || !(x[0] == 0 || x[1] == 0) || (x[0] == 0 && x[1] == 0)) continue;
    p.cloud.tags[si] = Tag::Neumann;
    p.cloud.normals[si] = x[0] == 0 ? Vec3(-1, 0, 0) : Vec3(0, -1, 0);
  }
  const Index n = p.cloud.size();
  p.f = Field::Zero(n);
  p.g.resize(n);
  p.q.resize(n);
  for (Index i = 0; i < n; ++i) {
    const Vec3& x = p.cloud.positions[static_cast<std::size_t>(i)];
    p.g[i] = x[0] + x[1];
    p.q[i] = Vec3(1, 1, 0).dot(p.cloud.normals[static_cast<std::size_t>(i)]);
  }
  BvpSolveOptions o;
  o.method = "fpm";
  const BvpSolution mixed = solve(p, o);
  EXPECT_GT(mixed.neumann_particles, 0);
  EXPECT_LT((mixed.u - p.g).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(SolveBvp, BadProblemsAreTypedErrors) {
  BoundaryValueProblem p;
  p.cloud = l_shape(8);
  p.f = Field::Zero(3);
  p.g = Field::Zero(p.cloud.size());
  EXPECT_THROW_MSG(solve(p), InputError, "f has 3 values for");
  p.f = Field::Zero(p.cloud.size());
  p.cloud.tags[0] = Tag::Neumann;  // no normals
  EXPECT_THROW_MSG(solve(p), InputError, "has no outward normal");
  p.cloud = l_shape(8);
  p.a = Field::Constant(p.cloud.size(), -1.0);
  EXPECT_THROW_MSG(solve(p), InputError, "coefficient a must be positive");
  p.a = Field();
  BvpSolveOptions o;
  o.method = "mfpm";
  EXPECT_THROW(solve(p, o), ConfigError);
  o.method = "vrsph";
  o.h_factor = 100;
  EXPECT_THROW_MSG(solve(p, o), ConfigError, "exceeds the extent");
}

TEST(SolveBvp, ValuesInsteadOfExpressions) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  // The same problem from expressions and from per-particle values (as --a-column etc.
  // give them) is the same problem.
  const PointCloud c = l_shape(16);
  const ExpressionProblem from_expr = problem_from_expressions(c, {"x*x + y", "1 + x", "", "", ""});
  const Field a = from_expr.problem.a, f = from_expr.problem.f, g = from_expr.problem.g;
  const ExpressionProblem from_values = problem_from_expressions(c, {"", "", "", "", ""}, {nullptr, &a, &f, &g, nullptr});
  EXPECT_EQ(from_values.problem.a, a);
  EXPECT_EQ(from_values.problem.f, f);
  EXPECT_EQ(from_values.problem.g, g);
  EXPECT_EQ(from_values.exact.size(), 0);
  // Misuse is named.
  EXPECT_THROW_MSG(problem_from_expressions(c, {"", "", "1", "", ""}, {nullptr, nullptr, &f, &g, nullptr}), ConfigError,
                   "give f either as an expression (--f) or as values (--f-column), not both");
  EXPECT_THROW_MSG(problem_from_expressions(c, {"x", "", "", "", ""}, {nullptr, &a, nullptr, nullptr, nullptr}), ConfigError,
                   "cannot be derived from values of a");
  const Field short_field = Field::Ones(3);
  EXPECT_THROW_MSG(problem_from_expressions(c, {"", "", "", "", ""}, {nullptr, nullptr, &f, &short_field, nullptr}),
                   InputError, "the Dirichlet data g (--g-column): 3 values for");
  Field bad = g;
  bad[4] = std::nan("");
  EXPECT_THROW_MSG(problem_from_expressions(c, {"", "", "", "", ""}, {nullptr, nullptr, &f, &bad, nullptr}), InputError,
                   "is not finite (nan) at particle 4");
}
