#include <cmath>
#include <memory>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/from_expressions.hpp>

namespace vrsph {

ExpressionProblem problem_from_expressions(PointCloud cloud, const ProblemExpressions& e) {
  validate(cloud);
  const int dim = cloud.dim;
  const bool has_u = !e.u.empty();
  const bool dirichlet = cloud.count(Tag::Dirichlet) > 0, neumann = cloud.count(Tag::Neumann) > 0;
  check<ConfigError>(has_u || !e.f.empty(), "without an exact solution --u the right-hand side --f is required");
  check<ConfigError>(has_u || !dirichlet || !e.g.empty(), "the cloud has ", cloud.count(Tag::Dirichlet),
                     " Dirichlet particles: give their values with --g (or an exact solution --u)");
  check<ConfigError>(has_u || !neumann || !e.q.empty(), "the cloud has ", cloud.count(Tag::Neumann),
                     " Neumann particles: give the flux a du/dn with --q (or an exact solution --u)");
  const auto u = has_u ? make_function_or_expression(e.u, dim) : nullptr;
  const auto a = make_function_or_expression(e.a.empty() ? "one" : e.a, dim);
  ExpressionProblem out;
  BoundaryValueProblem& p = out.problem;
  if (u) out.exact = sample(*u, cloud, "the exact solution u (--u)");
  p.a = sample(*a, cloud, "the coefficient a (--a)");
  const auto f = e.f.empty() ? std::unique_ptr<ScalarFunction>(std::make_unique<DivAGradOf>(*u, *a))
                             : make_function_or_expression(e.f, dim);
  p.f = sample(*f, cloud, e.f.empty() ? "the right-hand side f = div(a grad u)" : "the right-hand side f (--f)");
  if (!e.g.empty()) p.g = sample(*make_function_or_expression(e.g, dim), cloud, "the Dirichlet data g (--g)");
  else if (u) p.g = out.exact;
  else p.g = Field::Zero(cloud.size());  // no Dirichlet particle reads it
  if (neumann) {
    const auto q = e.q.empty() ? nullptr : make_function_or_expression(e.q, dim);
    p.q = Field::Zero(cloud.size());
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (cloud.tags[si] != Tag::Neumann) continue;
      const Vec3& x = cloud.positions[si];
      p.q[i] = q ? q->value(x) : p.a[i] * u->gradient(x).dot(cloud.normals[si]);
      check<InputError>(std::isfinite(p.q[i]), "the Neumann data q", q ? " (--q)" : " = a du/dn", " is not finite at particle ",
                        i, " (", x[0], ", ", x[1], ", ", x[2], ")");
    }
  }
  p.cloud = std::move(cloud);
  return out;
}

}  // namespace vrsph
