// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Exact scalar functions u(x) with gradient and Laplacian, from a built-in catalogue
// or from muParser expressions in x, y, z (constants pi and e). Used as manufactured
// solutions, coefficients a(x) and right-hand sides.
//
// Expression functions evaluate derivatives the user did not give by 4th-order
// central differences (step 1e-3 * max(1, |x|)), accurate to ~1e-10 for smooth
// functions. An Expression object is not thread-safe; sample() and sample_exact() give
// every thread its own copy (clone()), so sampling is parallel and its values do not
// depend on the thread count.
#include <memory>
#include <string>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/stencil/operator_kind.hpp>

namespace vrsph {

class ScalarFunction {
 public:
  virtual ~ScalarFunction() = default;
  virtual std::string name() const = 0;
  virtual Real value(const Vec3& x) const = 0;
  virtual Vec3 gradient(const Vec3& x) const;  ///< default: finite differences of value()
  virtual Real laplacian(const Vec3& x) const; ///< default: finite differences of value()
  /// An independent copy another thread may evaluate while this one is in use. The
  /// default (nullptr) marks a function that cannot be copied: it is then sampled serially.
  virtual std::unique_ptr<ScalarFunction> clone() const { return nullptr; }
  int dim = 2;
  /// The length over which the function varies, for finite-difference steps (1e-3 of it, or
  /// of |x_k| where that is larger): set to the cloud's length_scale, derivatives of an
  /// expression are the same in metres or millimetres. Copies keep it.
  Real length_scale = 1;
};

struct FunctionEntry {
  std::string name, formula;
};
/// cos-pi (prod cos(pi x_k), [QW] §6), sin-pi (prod sin(pi x_k), [QW] Ex. 5), exp-x (e^x, [AAR]),
/// one-plus-r2 (1 + |x|^2, [QW] Ex. 5 coefficient), one, linear (1 + x + 2y + 3z), quadratic.
const std::vector<FunctionEntry>& function_catalogue();
/// Throws ConfigError for an unknown name.
std::unique_ptr<ScalarFunction> make_function(const std::string& name, int dim);
/// u given by an expression; optional exact gradient components and Laplacian expressions
/// (empty strings: finite differences). Throws InputError if an expression does not parse.
std::unique_ptr<ScalarFunction> make_expression_function(const std::string& u, int dim,
                                                         const std::vector<std::string>& gradient = {},
                                                         const std::string& laplacian = "");

/// A catalogue name if it is one, else a muParser expression in x, y, z.
std::unique_ptr<ScalarFunction> make_function_or_expression(const std::string& spec, int dim);

/// A single muParser expression f(x, y, z), for right-hand sides and expected values.
class Expression {
 public:
  /// Throws InputError naming the expression and muParser's message if it does not parse.
  /// with_time: the expression may also use t (time-dependent data).
  Expression(const std::string& text, bool with_time = false);
  ~Expression();
  Expression(Expression&&) noexcept;
  Real operator()(const Vec3& x) const;
  /// At time t (for an expression made with_time; others do not depend on t).
  Real operator()(const Vec3& x, Real t) const;
  const std::string& text() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// f = div(a grad u) from u and a (exact for catalogue functions, finite differences of
/// expressions otherwise). Keeps references: u and a must outlive it (its clones own
/// clones of u and a).
class DivAGradOf final : public ScalarFunction {
 public:
  DivAGradOf(const ScalarFunction& u, const ScalarFunction& a) : u_(u), a_(a) { dim = u.dim; }
  std::string name() const override { return "div(a grad u)"; }
  Real value(const Vec3& x) const override;
  std::unique_ptr<ScalarFunction> clone() const override;

 private:
  DivAGradOf(std::shared_ptr<const ScalarFunction> u, std::shared_ptr<const ScalarFunction> a)
      : u_(*u), a_(*a), owned_u_(std::move(u)), owned_a_(std::move(a)) { dim = u_.dim; }
  const ScalarFunction& u_;
  const ScalarFunction& a_;
  std::shared_ptr<const ScalarFunction> owned_u_, owned_a_;  // set in clones only
};

/// f = div(M grad u) = Σ_k ∂_k(m_k ∂_k u) for a diagonal mobility M = diag(m_1..m_d), the
/// exact right-hand side of `--mobility` problems. ∂_k u and ∂_k m_k come from the functions'
/// gradients, ∂_kk u from 4th-order central differences of u (step 1e-3 max(1, |x_k|);
/// ~1e-10 relative for smooth u). Keeps references like DivAGradOf.
class DivMGradOf final : public ScalarFunction {
 public:
  DivMGradOf(const ScalarFunction& u, std::vector<const ScalarFunction*> m) : u_(u), m_(std::move(m)) { dim = u.dim; }
  std::string name() const override { return "div(M grad u)"; }
  Real value(const Vec3& x) const override;
  std::unique_ptr<ScalarFunction> clone() const override;

 private:
  const ScalarFunction& u_;
  std::vector<const ScalarFunction*> m_;
  std::vector<std::shared_ptr<const ScalarFunction>> owned_;  // set in clones only
};

/// Second derivative ∂²u/∂x_k² by 4th-order central differences of u.
Real second_derivative(const ScalarFunction& u, const Vec3& x, int k);

/// u at every particle; throws InputError naming the particle if a value is not finite.
Field sample(const ScalarFunction& u, const PointCloud& cloud);
/// The same, with the function's role in the problem first in the message (e.g. "the
/// exact solution u (--u)"), so a value that is not finite is named as the user gave it.
Field sample(const ScalarFunction& u, const PointCloud& cloud, const std::string& role);
/// N x dim matrix of grad u at the particles (the coefficient gradient of Taylor methods).
Eigen::MatrixXd sample_gradient(const ScalarFunction& u, const PointCloud& cloud);
/// Exact value of the operator applied to u at x (component c of the gradient);
/// DivAGrad needs a: a Δu + ∇a·∇u.
Real exact_operator(OperatorKind kind, const ScalarFunction& u, const ScalarFunction* a, const Vec3& x, int component);
/// N x components(kind, dim) matrix of exact values (rows of unwanted particles are 0).
Eigen::MatrixXd sample_exact(OperatorKind kind, const ScalarFunction& u, const ScalarFunction* a, const PointCloud& cloud);

}  // namespace vrsph
