// SPDX-License-Identifier: BSD-3-Clause
// Bad input never crashes and never yields silent garbage: every case below must
// raise the documented exception type with a message naming the problem.
#include <vrsph/analysis/operator_study.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
OperatorStudyParams small() {
  OperatorStudyParams p;
  p.n = {4, 8};
  return p;
}
}  // namespace

TEST(BadInput, UnknownNames) {
  auto p = small();
  p.methods = {"sph", "magic"};
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "unknown method 'magic'");
  p = small();
  p.problem = "qw-nothing";
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "unknown operator problem 'qw-nothing'");
  EXPECT_THROW_MSG(parse_cloud_family("lattice"), ConfigError, "unknown cloud family 'lattice'");
  p = small();
  p.method_options["sph"] = MethodOptions::parse({"colour=red"});
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "method sph has no option(s): colour");
}

TEST(BadInput, NonPositiveSmoothingLengthAndRefinement) {
  auto p = small();
  p.h_factor = 0;
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "h-factor must be positive and finite, got 0");
  p = small();
  p.n = {8, 0};
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "refinement level n = 0");
  p = small();
  p.dim = 4;
  EXPECT_THROW_MSG(run_operator_study(p), ConfigError, "--dim must be 1, 2 or 3, got 4");
}

TEST(BadInput, NonPositiveCoefficient) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  auto p = small();
  p.op = OperatorKind::DivAGrad;
  p.a = "x";  // a <= 0 on half of [-1,1]^2
  EXPECT_THROW_MSG(run_operator_study(p), InputError, "coefficient a must be positive and finite: a = -");
  p.a = "log(x)";  // NaN for x < 0
  EXPECT_THROW_MSG(run_operator_study(p), InputError, "is not finite");
}

TEST(BadInput, UnparsableExpressionsAndComponentMismatch) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  auto p = small();
  p.u = "cos(pi*x";
  EXPECT_THROW_MSG(run_operator_study(p), InputError, "cannot parse expression 'cos(pi*x'");
  p = small();
  p.u = "x*y";
  p.op = OperatorKind::Gradient;
  p.exact = "y";
  EXPECT_THROW_MSG(run_operator_study(p), InputError, "--exact gives 1 expression(s) but operator gradient has 2");
}

TEST(BadInput, ParticleWithoutNeighbours) {
  PointCloud c = vertex_lattice(Domain::unit_box(2), 4);
  c.add(Vec3(5, 5, 0), Tag::Interior);
  SearchParams sp;
  sp.radius = 0.6;
  EXPECT_THROW_MSG(find_neighbours(c, sp), GeometryError, "particle 25 at (5, 5, 0) has 0 neighbours within radius 0.6");
}

TEST(BadInput, MethodDoesNotProvideOperatorOrCoefficientMissing) {
  PointCloud c = vertex_lattice(Domain::unit_box(2), 4);
  SearchParams sp;
  sp.radius = 0.6;
  const NeighbourList nl = find_neighbours(c, sp);
  const auto m = builtin_methods().create("sph");
  EXPECT_THROW_MSG(m->build({c, nl, KernelType::CubicSpline, c.spacing}, {OperatorKind::DivAGrad}), InputError,
                   "div-a-grad needs the coefficient a");
  Field a = Field::Ones(3);
  EXPECT_THROW_MSG(m->build({c, nl, KernelType::CubicSpline, c.spacing}, {OperatorKind::DivAGrad, &a}), InputError,
                   "coefficient a has 3 values for 25 particles");
  EXPECT_THROW_MSG(m->build({c, nl, KernelType::CubicSpline, 0.0}, {OperatorKind::Laplacian}), InputError,
                   "need a positive particle spacing");
}
