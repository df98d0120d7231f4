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

namespace {
// Each role given once, enough data for the tags in the cloud, the given values valid.
void check_roles(const PointCloud& cloud, const ProblemExpressions& e, const ProblemValues& v) {
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
    check<ConfigError>(static_cast<int>(e.mobility.size()) == cloud.dim, "--mobility needs one expression per direction (",
                       cloud.dim, " in ", cloud.dim, "D), got ", e.mobility.size());
  }
}

// The problem's functions, their derivatives by finite differences in the cloud's own unit.
struct ProblemFunctions {
  std::unique_ptr<ScalarFunction> u, a;
  std::vector<std::unique_ptr<ScalarFunction>> mobility;
};

// f: given, from its expression, or div(a grad u) / div(M grad u) of the exact solution.
Field right_hand_side(const PointCloud& cloud, const ProblemExpressions& e, const ProblemValues& v,
                      const ProblemFunctions& fn, Real length) {
  if (v.f) return *v.f;
  if (!e.f.empty()) return sample(*make_function_or_expression(e.f, cloud.dim), cloud, "the right-hand side f (--f)");
  if (fn.mobility.empty()) {
    DivAGradOf f(*fn.u, *fn.a);
    f.length_scale = length;
    return sample(f, cloud, "the right-hand side f = div(a grad u)");
  }
  std::vector<const ScalarFunction*> m;
  for (const auto& mk : fn.mobility) m.push_back(mk.get());
  DivMGradOf f(*fn.u, std::move(m));
  f.length_scale = length;
  return sample(f, cloud, "the right-hand side f = div(M grad u)");
}

// q at the Neumann particles: given, from its expression, or (a or M) grad u · n.
Field neumann_data(const PointCloud& cloud, const ProblemExpressions& e, const ProblemValues& v,
                   const ProblemFunctions& fn, const BoundaryValueProblem& p) {
  const auto q = e.q.empty() ? nullptr : make_function_or_expression(e.q, cloud.dim);
  Field out = Field::Zero(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (cloud.tags[si] != Tag::Neumann) continue;
    const Vec3& x = cloud.positions[si];
    if (v.q) {
      out[i] = (*v.q)[i];
    } else if (q) {
      out[i] = q->value(x);
    } else {
      const Vec3 gu = fn.u->gradient(x);
      if (fn.mobility.empty()) out[i] = p.a[i] * gu.dot(cloud.normals[si]);
      for (int k = 0; k < static_cast<int>(fn.mobility.size()); ++k) out[i] += cloud.normals[si][k] * p.mobility(i, k) * gu[k];
    }
    check<InputError>(std::isfinite(out[i]), "the Neumann data q", q ? " (--q)" : " = a du/dn", " is not finite at particle ",
                      i, " (", x[0], ", ", x[1], ", ", x[2], ")");
  }
  return out;
}
}  // namespace

ExpressionProblem problem_from_expressions(PointCloud cloud, const ProblemExpressions& e, const ProblemValues& v) {
  if (cloud.size() > 0) validate(cloud);  // (an empty cloud: one rank's part; the solve names a cloud that is all empty)
  const int dim = cloud.dim;
  check_roles(cloud, e, v);
  ProblemFunctions fn;
  if (!e.u.empty()) fn.u = make_function_or_expression(e.u, dim);
  for (const auto& m : e.mobility) fn.mobility.push_back(make_function_or_expression(m, dim));
  if (!v.a) fn.a = make_function_or_expression(e.a.empty() ? "one" : e.a, dim);
  // Derivatives of u, a and M by finite differences in the cloud's own unit.
  const Real length = e.length_scale > 0 ? e.length_scale : length_scale(cloud);
  for (ScalarFunction* f : {fn.u.get(), fn.a.get()})
    if (f) f->length_scale = length;
  for (auto& m : fn.mobility) m->length_scale = length;
  ExpressionProblem out;
  BoundaryValueProblem& p = out.problem;
  if (fn.u) out.exact = sample(*fn.u, cloud, "the exact solution u (--u)");
  else if (v.u) out.exact = *v.u;
  if (fn.mobility.empty()) {
    p.a = v.a ? *v.a : sample(*fn.a, cloud, "the coefficient a (--a)");
  } else {
    p.mobility.resize(cloud.size(), dim);
    for (int k = 0; k < dim; ++k)
      p.mobility.col(k) = sample(*fn.mobility[static_cast<std::size_t>(k)], cloud, detail::concat("the mobility m_", k + 1, " (--mobility)"));
  }
  p.f = right_hand_side(cloud, e, v, fn, length);
  const bool has_u = !e.u.empty() || v.u;
  if (v.g) p.g = *v.g;
  else if (!e.g.empty()) p.g = sample(*make_function_or_expression(e.g, dim), cloud, "the Dirichlet data g (--g)");
  else if (has_u) p.g = out.exact;
  else p.g = Field::Zero(cloud.size());  // no Dirichlet particle reads it
  if (cloud.count(Tag::Neumann) > 0) p.q = neumann_data(cloud, e, v, fn, p);
  p.cloud = std::move(cloud);
  return out;
}

}  // namespace vrsph
