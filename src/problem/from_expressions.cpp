// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <memory>
#include <tuple>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/from_expressions.hpp>

namespace vrsph {

namespace {
// Checks a value array for a role: one finite value per particle.
void check_values(const Field& v, const PointCloud& cloud, const char* role) {
  check<InputError>(v.size() == cloud.size(), role, ": ", v.size(), " values for ", cloud.size(), " particles");
  for (Index i = 0; i < v.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    check<InputError>(std::isfinite(v[i]), role, " is not finite (", v[i], ") at particle ", i, " (", x[0], ", ", x[1],
                      ", ", x[2], ")");
  }
}
}  // namespace

ExpressionProblem problem_from_expressions(PointCloud cloud, const ProblemExpressions& e, const ProblemValues& v) {
  if (cloud.size() > 0) validate(cloud);  // (an empty cloud: one rank's part; the solve names a cloud that is all empty)
  const int dim = cloud.dim;
  for (const auto& [expr, values, role] : {std::tuple{&e.u, v.u, "u"}, std::tuple{&e.a, v.a, "a"},
                                          std::tuple{&e.f, v.f, "f"}, std::tuple{&e.g, v.g, "g"},
                                          std::tuple{&e.q, v.q, "q"}})
    check<ConfigError>(expr->empty() || values == nullptr, "give ", role, " either as an expression (--", role,
                       ") or as values (--", role, "-column), not both");
  const bool has_u = !e.u.empty() || v.u;
  const bool has_f = !e.f.empty() || v.f;
  const bool dirichlet = cloud.count(Tag::Dirichlet) > 0, neumann = cloud.count(Tag::Neumann) > 0;
  check<ConfigError>(has_u || has_f, "without an exact solution --u the right-hand side --f is required");
  check<ConfigError>(has_f || (!v.u && !v.a), "f = div(a grad u) cannot be derived from values of ", v.u ? "u" : "a",
                     " (a column): give the right-hand side --f or --f-column");
  check<ConfigError>(has_u || !dirichlet || !e.g.empty() || v.g, "the cloud has ", cloud.count(Tag::Dirichlet),
                     " Dirichlet particles: give their values with --g (or an exact solution --u)");
  check<ConfigError>(has_u || !neumann || !e.q.empty() || v.q, "the cloud has ", cloud.count(Tag::Neumann),
                     " Neumann particles: give the flux a du/dn with --q (or an exact solution --u)");
  check<ConfigError>(!neumann || !e.q.empty() || v.q || !v.u, "the cloud has ", cloud.count(Tag::Neumann),
                     " Neumann particles and u is given as values: a du/dn cannot be derived, give --q or --q-column");
  for (const auto& [values, role] : {std::pair{v.u, "the exact solution u (--u-column)"},
                                     std::pair{v.a, "the coefficient a (--a-column)"},
                                     std::pair{v.f, "the right-hand side f (--f-column)"},
                                     std::pair{v.g, "the Dirichlet data g (--g-column)"},
                                     std::pair{v.q, "the Neumann data q (--q-column)"}})
    if (values) check_values(*values, cloud, role);
  if (!e.mobility.empty()) {
    check<ConfigError>(e.a.empty() && !v.a, "a scalar coefficient a and a mobility (--mobility) exclude each other");
    check<ConfigError>(static_cast<int>(e.mobility.size()) == dim, "--mobility needs one expression per direction (",
                       dim, " in ", dim, "D), got ", e.mobility.size());
  }
  const auto u = e.u.empty() ? nullptr : make_function_or_expression(e.u, dim);
  std::vector<std::unique_ptr<ScalarFunction>> mob;
  for (const auto& m : e.mobility) mob.push_back(make_function_or_expression(m, dim));
  const auto a = v.a ? nullptr : make_function_or_expression(e.a.empty() ? "one" : e.a, dim);
  // Derivatives of u, a and M by finite differences in the cloud's own unit.
  const Real length = e.length_scale > 0 ? e.length_scale : length_scale(cloud);
  for (ScalarFunction* fn : {u.get(), a.get()})
    if (fn) fn->length_scale = length;
  for (auto& m : mob) m->length_scale = length;
  ExpressionProblem out;
  BoundaryValueProblem& p = out.problem;
  if (u) out.exact = sample(*u, cloud, "the exact solution u (--u)");
  else if (v.u) out.exact = *v.u;
  if (mob.empty()) {
    p.a = v.a ? *v.a : sample(*a, cloud, "the coefficient a (--a)");
  } else {
    p.mobility.resize(cloud.size(), dim);
    for (int k = 0; k < dim; ++k)
      p.mobility.col(k) = sample(*mob[static_cast<std::size_t>(k)], cloud, detail::concat("the mobility m_", k + 1, " (--mobility)"));
  }
  if (v.f) {
    p.f = *v.f;
  } else if (!e.f.empty()) {
    p.f = sample(*make_function_or_expression(e.f, dim), cloud, "the right-hand side f (--f)");
  } else if (mob.empty()) {
    DivAGradOf f(*u, *a);
    f.length_scale = length;
    p.f = sample(f, cloud, "the right-hand side f = div(a grad u)");
  } else {
    std::vector<const ScalarFunction*> m;
    for (const auto& mk : mob) m.push_back(mk.get());
    DivMGradOf f(*u, std::move(m));
    f.length_scale = length;
    p.f = sample(f, cloud, "the right-hand side f = div(M grad u)");
  }
  if (v.g) p.g = *v.g;
  else if (!e.g.empty()) p.g = sample(*make_function_or_expression(e.g, dim), cloud, "the Dirichlet data g (--g)");
  else if (has_u) p.g = out.exact;
  else p.g = Field::Zero(cloud.size());  // no Dirichlet particle reads it
  if (neumann) {
    const auto q = e.q.empty() ? nullptr : make_function_or_expression(e.q, dim);
    p.q = Field::Zero(cloud.size());
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (cloud.tags[si] != Tag::Neumann) continue;
      const Vec3& x = cloud.positions[si];
      if (v.q) {
        p.q[i] = (*v.q)[i];
      } else if (q) {
        p.q[i] = q->value(x);
      } else {
        const Vec3 gu = u->gradient(x);
        p.q[i] = 0;
        if (mob.empty()) p.q[i] = p.a[i] * gu.dot(cloud.normals[si]);
        for (int k = 0; k < static_cast<int>(mob.size()); ++k) p.q[i] += cloud.normals[si][k] * p.mobility(i, k) * gu[k];
      }
      check<InputError>(std::isfinite(p.q[i]), "the Neumann data q", q ? " (--q)" : " = a du/dn", " is not finite at particle ",
                        i, " (", x[0], ", ", x[1], ", ", x[2], ")");
    }
  }
  p.cloud = std::move(cloud);
  return out;
}

}  // namespace vrsph
