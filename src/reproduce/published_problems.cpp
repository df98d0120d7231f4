// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/reproduce/problem_defaults.hpp>
#include <vrsph/reproduce/published_problems.hpp>
#include <vrsph/reproduce/spe_problems.hpp>

namespace vrsph {

namespace {
StudyProblem aar_static(const BvpStudyParams& p) {
  check<ConfigError>(p.u.empty() && p.a.empty() && p.f.empty() && p.g.empty(),
                     "--u/--a/--f/--g define a custom problem: use them without --problem aar-static");
  check<ConfigError>(p.dim == 1, "problem aar-static is one-dimensional (--dim 1)");
  StudyProblem sp;
  // u = -e^x + e x + 1 with exact derivatives; -u'' = e^x, i.e. div(grad u) = f = -e^x.
  sp.u = make_expression_function("-exp(x) + e*x + 1", 1, {"-exp(x) + e"}, "-exp(x)");
  sp.a = make_function("one", 1);
  sp.f = make_expression_function("-exp(x)", 1);
  sp.g = sp.u;
  sp.neumann = {"x1"};
  return sp;
}

StudyProblem spe_laplace(const BvpStudyParams& p) {
  check<ConfigError>(p.u.empty() && p.a.empty() && p.f.empty() && p.g.empty(),
                     "--u/--a/--f/--g define a custom problem: use them without --problem ", p.problem);
  check<ConfigError>(p.dim == 2, "problem ", p.problem, " is two-dimensional (--dim 2)");
  StudyProblem sp;
  sp.u = make_spe_function(p.problem);
  sp.a = make_function("one", 2);
  sp.f = make_expression_function("0", 2);
  if (p.problem == "spe-dirichlet") {
    sp.g = make_spe_function("spe-dirichlet-boundary");
  } else {
    sp.g = sp.u;  // u(x, 0) = ψ1 exactly
    sp.flux = [](const Vec3& x, const Vec3&) { return spe_mixed_flux(x, SpeBoundaryData{}); };
    sp.neumann = {"x0", "x1", "y1"};
  }
  sp.support_per_h_factor = problem_defaults(p.problem).support_per_h_factor;
  return sp;
}
}  // namespace

StudyProblemCatalogue published_problems() {
  StudyProblemCatalogue c;
  c.names = {"aar-static", "spe-dirichlet", "spe-mixed"};
  c.make = [](const BvpStudyParams& p) { return p.problem == "aar-static" ? aar_static(p) : spe_laplace(p); };
  return c;
}

}  // namespace vrsph
