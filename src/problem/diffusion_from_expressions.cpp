// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/diffusion_from_expressions.hpp>

namespace vrsph {

namespace {

using Shared = std::shared_ptr<const Expression>;

// u(·, t) at one time as a ScalarFunction: its gradient and Laplacian are the base class's
// finite differences, which DivAGradOf and DivMGradOf use.
class AtTime final : public ScalarFunction {
 public:
  AtTime(Shared e, int d, Real t) : e_(std::move(e)), t_(t) { dim = d; }
  std::string name() const override { return e_->text(); }
  Real value(const Vec3& x) const override { return (*e_)(x, t_); }

 private:
  Shared e_;
  Real t_;
};

// ∂u/∂t by the fourth-order central difference.
Real time_derivative(const Expression& u, const Vec3& x, Real t) {
  const Real h = 1e-3 * std::max<Real>(1, std::abs(t));
  return (-u(x, t + 2 * h) + 8 * u(x, t + h) - 8 * u(x, t - h) + u(x, t - 2 * h)) / (12 * h);
}

Field sample_positive(const ScalarFunction& f, const PointCloud& cloud, const std::string& role) {
  Field v(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    v[i] = f.value(x);
    check<InputError>(std::isfinite(v[i]) && v[i] > 0, role, " must be positive and finite, got ", v[i],
                      " at particle ", i, " (", x[0], ", ", x[1], ", ", x[2], ")");
  }
  return v;
}

}  // namespace

DiffusionProblem diffusion_from_expressions(PointCloud cloud, const DiffusionExpressions& e) {
  validate(cloud);
  const int dim = cloud.dim;
  const bool has_u = !e.u.empty();
  const bool dirichlet = cloud.count(Tag::Dirichlet) > 0, neumann = cloud.count(Tag::Neumann) > 0;
  check<ConfigError>(has_u || !e.s.empty(), "without an exact solution --u the source --s is required");
  check<ConfigError>(has_u || !e.u0.empty(), "without an exact solution --u the initial values --u0 are required");
  check<ConfigError>(has_u || !dirichlet || !e.g.empty(), "the cloud has ", cloud.count(Tag::Dirichlet),
                     " Dirichlet particles: give their values with --g (or an exact solution --u)");
  check<ConfigError>(has_u || !neumann || !e.q.empty(), "the cloud has ", cloud.count(Tag::Neumann),
                     " Neumann particles: give the flux with --q (or an exact solution --u)");
  check<ConfigError>(e.mobility.empty() || e.a.empty(), "a scalar coefficient a and a mobility (--mobility) exclude each other");
  check<ConfigError>(e.mobility.empty() || static_cast<int>(e.mobility.size()) == dim,
                     "--mobility needs one expression per direction (", dim, " in ", dim, "D), got ", e.mobility.size());

  DiffusionProblem p;
  p.cloud = std::move(cloud);
  const PointCloud& c = p.cloud;
  // The coefficient: constant in time, sampled once (the stencil is built once).
  std::vector<std::shared_ptr<const ScalarFunction>> mob;
  for (const auto& m : e.mobility) mob.push_back(make_function_or_expression(m, dim));
  const std::shared_ptr<const ScalarFunction> a = make_function_or_expression(e.a.empty() ? "one" : e.a, dim);
  if (mob.empty()) {
    p.a = sample_positive(*a, c, "the coefficient a (--a)");
  } else {
    p.mobility.resize(c.size(), dim);
    for (int k = 0; k < dim; ++k)
      p.mobility.col(k) = sample_positive(*mob[static_cast<std::size_t>(k)], c, detail::concat("mobility m", k + 1));
  }
  const Shared u = has_u ? std::make_shared<const Expression>(e.u, true) : nullptr;
  const auto given = [](const std::string& text) { return std::make_shared<const Expression>(text, true); };
  if (u) p.exact = [u](const Vec3& x, Real t) { return (*u)(x, t); };
  // div(a grad u) or div(M grad u) of u(·, t).
  const auto space = [u, a, mob, dim](const Vec3& x, Real t) {
    const AtTime ut(u, dim, t);
    if (mob.empty()) return DivAGradOf(ut, *a).value(x);
    std::vector<const ScalarFunction*> m;
    for (const auto& f : mob) m.push_back(f.get());
    return DivMGradOf(ut, m).value(x);
  };
  if (!e.s.empty()) {
    const Shared s = given(e.s);
    p.source = [s](const Vec3& x, Real t) { return (*s)(x, t); };
  } else {
    p.source = [u, space](const Vec3& x, Real t) { return time_derivative(*u, x, t) - space(x, t); };
  }
  if (!e.g.empty()) {
    const Shared g = given(e.g);
    p.boundary = [g](const Vec3& x, Real t) { return (*g)(x, t); };
  } else if (u) {
    p.boundary = p.exact;
  }
  if (neumann) {
    check<InputError>(c.has_normals(), "Neumann particles need outward normals");
    // q at a Neumann particle, located by its position (the normals come from the cloud).
    if (!e.q.empty()) {
      const Shared q = given(e.q);
      p.flux = [q](const Vec3& x, Real t) { return (*q)(x, t); };
    } else {
      const auto normals = std::make_shared<std::map<std::array<Real, 3>, Vec3>>();
      for (Index i = 0; i < c.size(); ++i)
        if (c.tags[static_cast<std::size_t>(i)] == Tag::Neumann) {
          const Vec3& x = c.positions[static_cast<std::size_t>(i)];
          (*normals)[{x[0], x[1], x[2]}] = c.normals[static_cast<std::size_t>(i)];
        }
      p.flux = [u, a, mob, dim, normals](const Vec3& x, Real t) {
        const auto it = normals->find({x[0], x[1], x[2]});
        check<InputError>(it != normals->end(), "flux data requested at (", x[0], ", ", x[1], ", ", x[2],
                          "), which is not a Neumann particle");
        const Vec3& n = it->second;
        const Vec3 grad = AtTime(u, dim, t).gradient(x);
        Real q = 0;
        for (int k = 0; k < dim; ++k) q += n[k] * (mob.empty() ? a->value(x) : mob[static_cast<std::size_t>(k)]->value(x)) * grad[k];
        return q;
      };
    }
  }
  p.u0.resize(c.size());
  const Shared u0 = e.u0.empty() ? nullptr : std::make_shared<const Expression>(e.u0);
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& x = c.positions[static_cast<std::size_t>(i)];
    p.u0[i] = u0 ? (*u0)(x) : (*u)(x, 0.0);
    check<InputError>(std::isfinite(p.u0[i]), "the initial value is not finite (", p.u0[i], ") at particle ", i);
  }
  return p;
}

}  // namespace vrsph
