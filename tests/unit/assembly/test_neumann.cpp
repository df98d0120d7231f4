// SPDX-License-Identifier: BSD-3-Clause
// Neumann and mixed boundary conditions through the flux rows of the method's own
// gradient: exactness on fields every method's gradient reproduces, the corner rule, and
// the singular pure-Neumann problem.
#include <cmath>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
BvpRun solve_custom(const std::string& method, int dim, const std::string& u, std::vector<std::string> neumann,
                    bool fix_constant = false, CloudFamily cloud = CloudFamily::Perturbed,
                    const std::string& gradient_order = "") {
  BvpStudyParams p;
  if (!gradient_order.empty()) p.method_options[method].set("gradient_order", gradient_order);
  p.problem = "custom";
  p.dim = dim;
  p.u = u;
  p.a = "1 + x*x";
  p.methods = {method};
  p.cloud = cloud;
  p.neumann = std::move(neumann);
  p.fix_constant = fix_constant;
  p.check_m_matrix = false;
  return run_bvp(p, method, dim == 1 ? 40 : 16, 3, false);
}
}  // namespace

TEST(Neumann, MixedProblemExactForLinearSolutions) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  // a = 1 + x^2, u linear: f = a' u_x; every corrected gradient is exact for linear u, and
  // the Taylor methods' div(a grad) (a Δ_h u + ∇a·∇_h u) is exact too.
  for (const auto* m : {"fpm", "kgf", "cspm"}) {
    const BvpRun r = solve_custom(m, 2, "1 + 2*x - y", {"x1", "y0"});
    EXPECT_GT(r.neumann_particles, 20) << m;
    // FPM's and KGF's default flux rows are exact on cubics; a one-sided cubic row has larger
    // weights of both signs than the linear fit's, and the solve's rounding grows with them
    // (measured 2.2e-10 with FPM and 3.1e-9 with KGF here, 4.5e-8 in the pure Neumann problem
    // below; the rows themselves reproduce a linear gradient to 4e-13).
    EXPECT_LT(r.errors.all.linf, std::string(m) == "cspm" ? 1e-9 : 1e-7) << m;
    for (const char* order : {"1", "2"}) {
      if (std::string(m) == "cspm") continue;
      EXPECT_LT(solve_custom(m, 2, "1 + 2*x - y", {"x1", "y0"}, false, CloudFamily::Perturbed, order).errors.all.linf, 1e-9)
          << m << " gradient_order=" << order;
    }
  }
  for (const auto* m : {"fpm2o", "mfpm", "fpm"}) {
    const BvpRun r = solve_custom(m, 1, "3 - 2*x", {"x1"});
    EXPECT_EQ(r.neumann_particles, 1) << m;
    EXPECT_LT(r.errors.all.linf, 1e-9) << m;
  }
}

TEST(Neumann, CornersBetweenNeumannFacesGetTheAveragedNormal) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  const BvpRun r = solve_custom("fpm", 2, "1 + x + y", {"x1", "y1"}, false, CloudFamily::Uniform);
  // Neumann particles: the faces x = 1 and y = 1 without their Dirichlet ends, plus the shared corner.
  EXPECT_EQ(r.neumann_particles, 2 * 15 + 1);
  EXPECT_LT(r.errors.all.linf, 1e-9);
}

TEST(Neumann, PureNeumannIsSingularUnlessTheConstantIsFixed) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  EXPECT_THROW_MSG((void)solve_custom("fpm", 2, "1 + x - y", {"all"}), InputError, "up to a constant");
  EXPECT_LT(solve_custom("fpm", 2, "1 + x - y", {"all"}, true).errors.all.linf, 1e-7);  // measured 4.5e-8
  EXPECT_LT(solve_custom("fpm", 2, "1 + x - y", {"all"}, true, CloudFamily::Perturbed, "1").errors.all.linf, 1e-9);
}

// VRSPH's balance rows keep -L an M-matrix with every face Neumann once one unknown is pinned:
// the pinned particle anchors the chains of the M-matrix test as a Dirichlet particle does (it
// read "not an M-matrix" for every pure-Neumann problem before).
TEST(Neumann, PureNeumannWithAPinnedUnknownIsAnMMatrix) {
  VRSPH_REQUIRE_PART("MUPARSER");
  BvpStudyParams p;
  p.problem = "custom";
  p.dim = 2;
  p.u = "x^3 + y^3 + x*y";
  p.methods = {"vrsph"};
  p.cloud = CloudFamily::Perturbed;
  p.neumann = {"all"};
  p.fix_constant = true;
  for (const int n : {16, 32}) {
    const BvpRun r = run_bvp(p, "vrsph", n, 3, false);
    EXPECT_TRUE(r.m_matrix) << n << ": " << r.m_matrix_summary;
    EXPECT_GT(r.neumann_particles, 4 * n - 4);
    EXPECT_LT(r.errors.all.linf, n == 16 ? 2e-3 : 3e-4) << n;  // measured 5.9e-4, 9.0e-5
  }
}

TEST(Neumann, ParticleWithoutNormalIsAnError) {
  PointCloud c = vertex_lattice(Domain::unit_box(2), 4);
  Index target = -1;
  for (Index i = 0; i < c.size(); ++i)
    if (c.tags[static_cast<std::size_t>(i)] == Tag::Dirichlet && target < 0) target = i;
  c.tags[static_cast<std::size_t>(target)] = Tag::Neumann;
  c.normals.assign(static_cast<std::size_t>(c.size()), Vec3::Zero());
  std::vector<char> unknown(static_cast<std::size_t>(c.size()));
  for (Index i = 0; i < c.size(); ++i) unknown[static_cast<std::size_t>(i)] = c.tags[static_cast<std::size_t>(i)] != Tag::Dirichlet;
  Stencil L;  // never reached: the flux checks come first
  L.row_ptr.assign(static_cast<std::size_t>(c.size()) + 1, 0);
  L.values.assign(1, {});
  Stencil G = L;
  G.kind = OperatorKind::Gradient;
  BoundaryRows bc;
  bc.gradient = &G;
  bc.q = Field::Zero(c.size());
  const Field zero = Field::Zero(c.size());
  EXPECT_THROW_MSG((void)assemble(L, c, unknown, zero, zero, &bc), InputError, "has no outward normal");
  EXPECT_THROW_MSG((void)assemble(L, c, unknown, zero, zero), InputError, "no flux (gradient) stencil");
}

TEST(Neumann, QuadraticFitFluxRowsGiveSecondOrderMixedProblems) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  // fpm gradient_order=2: flux rows from the quadratic fit are second-order one-sided
  // gradients, so the mixed problem converges at order 2 (order 1 with the linear fit, [QW]'s
  // gradient_order=1; at least 2 with the default rows, exact on cubics).
  BvpStudyParams p;
  p.problem = "custom";
  p.u = "x*y + exp(x)";
  p.methods = {"fpm"};
  p.method_options["fpm"].set("gradient_order", "2");
  p.cloud = CloudFamily::Uniform;
  p.neumann = {"x1", "y1"};
  p.n = {16, 32, 64};
  p.check_m_matrix = false;
  EXPECT_GE(run_bvp_study(p).fitted_order_inf.at("fpm"), 1.8);
  p.method_options.clear();
  EXPECT_GE(run_bvp_study(p).fitted_order_inf.at("fpm"), 1.8);
  p.method_options["fpm"].set("gradient_order", "1");
  const double linear = run_bvp_study(p).fitted_order_inf.at("fpm");
  EXPECT_NEAR(linear, 1.0, 0.2);
}

// Robin rows a du/dn + beta u = q from each method's own gradient (issue 17 item 2): exact on
// linear solutions, well-posed without any Dirichlet particle, second order with FPM's
// second-order gradient, and a negative beta refused.
TEST(Robin, ExactOnLinearsAndWellPosedWithoutDirichletData) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  for (const char* method : {"m-sph", "fpm", "sph"}) {
    BvpStudyParams p;
    p.problem = "custom";
    p.u = "1 + x + 2*y";
    p.methods = {method};
    p.robin = {"all"};  // no Dirichlet particle at all
    p.beta = "1 + x*y";
    p.n = {10};
    if (std::string(method) == "fpm") p.method_options["fpm"].set("gradient_order", "2");
    if (std::string(method) == "m-sph") p.kernel = KernelType::CubicSplineSPE;
    const BvpStudyResult r = run_bvp_study(p);
    if (std::string(method) == "sph") {
      EXPECT_TRUE(std::isfinite(r.rows.front().error_inf));  // SPH is not exact on linears near walls; solvable
      continue;
    }
    EXPECT_LT(r.rows.front().error_inf, 1e-9) << method;
  }
}

TEST(Robin, SecondOrderWithFpmAndBetaRefusedBelowZero) {
  VRSPH_REQUIRE_PART("MUPARSER");  // its data are expressions
  BvpStudyParams p;
  p.problem = "custom";
  p.u = "exp(x)*sin(2*y) + x*x";
  p.a = "1 + x*y";
  p.methods = {"fpm"};
  p.method_options["fpm"].set("gradient_order", "2");
  p.robin = {"all"};
  p.beta = "2";
  p.n = {20, 40, 80};
  const BvpStudyResult r = run_bvp_study(p);
  // Measured 6.6e-3, 1.25e-3, 2.96e-4: orders 2.40, 2.08.
  for (std::size_t k = 1; k < r.rows.size(); ++k) EXPECT_GE(r.rows[k].order_inf, 1.8) << r.rows[k].first.n;
  p.beta = "x - 2";
  p.n = {10};
  EXPECT_THROW_MSG(run_bvp_study(p), InputError, "must be finite and >= 0");
  p.beta = "1";
  p.neumann = {"x1"};
  EXPECT_THROW_MSG(run_bvp_study(p), ConfigError, "is both Neumann and Robin");
}
