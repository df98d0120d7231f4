// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <exception>
#include <numbers>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include "../core/first_failure.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vrsph {

Vec3 ScalarFunction::gradient(const Vec3& x) const {
  Vec3 g = Vec3::Zero();
  for (int k = 0; k < dim; ++k) {
    const Real d = 1e-3 * std::max<Real>(length_scale, std::abs(x[k]));
    Vec3 e = Vec3::Zero();
    e[k] = d;
    g[k] = (8 * (value(x + e) - value(x - e)) - (value(x + 2 * e) - value(x - 2 * e))) / (12 * d);
  }
  return g;
}

Real ScalarFunction::laplacian(const Vec3& x) const {
  Real s = 0;
  const Real u0 = value(x);
  for (int k = 0; k < dim; ++k) {
    const Real d = 1e-3 * std::max<Real>(length_scale, std::abs(x[k]));
    Vec3 e = Vec3::Zero();
    e[k] = d;
    s += (-(value(x + 2 * e) + value(x - 2 * e)) + 16 * (value(x + e) + value(x - e)) - 30 * u0) / (12 * d * d);
  }
  return s;
}

namespace {
constexpr Real pi = std::numbers::pi;

class ProductTrig final : public ScalarFunction {  // prod_k f(pi x_k), f = cos or sin
 public:
  ProductTrig(bool cosine, int d) : cos_(cosine) { dim = d; }
  std::string name() const override { return cos_ ? "cos-pi" : "sin-pi"; }
  Real f(Real t) const { return cos_ ? std::cos(pi * t) : std::sin(pi * t); }
  Real df(Real t) const { return cos_ ? -pi * std::sin(pi * t) : pi * std::cos(pi * t); }
  Real value(const Vec3& x) const override {
    Real p = 1;
    for (int k = 0; k < dim; ++k) p *= f(x[k]);
    return p;
  }
  Vec3 gradient(const Vec3& x) const override {
    Vec3 g = Vec3::Zero();
    for (int k = 0; k < dim; ++k) {
      Real p = df(x[k]);
      for (int l = 0; l < dim; ++l)
        if (l != k) p *= f(x[l]);
      g[k] = p;
    }
    return g;
  }
  Real laplacian(const Vec3& x) const override { return -dim * pi * pi * value(x); }
  std::unique_ptr<ScalarFunction> clone() const override { return std::make_unique<ProductTrig>(*this); }

 private:
  bool cos_;
};

class Polynomial final : public ScalarFunction {
 public:
  enum Kind { One, Linear, Quadratic, OnePlusR2 };
  Polynomial(Kind k, int d) : kind_(k) { dim = d; }
  std::string name() const override {
    switch (kind_) {
      case One: return "one";
      case Linear: return "linear";
      case Quadratic: return "quadratic";
      case OnePlusR2: return "one-plus-r2";
    }
    return "";
  }
  Real value(const Vec3& x) const override {
    switch (kind_) {
      case One: return 1;
      case Linear: return 1 + x[0] + 2 * x[1] + 3 * x[2];
      case Quadratic: return 1 + x[0] - x[1] + x[0] * x[0] + 2 * x[0] * x[1] + 3 * x[1] * x[1] - x[2] * x[2] + x[0] * x[2];
      case OnePlusR2: return 1 + x.squaredNorm();
    }
    return 0;
  }
  Vec3 gradient(const Vec3& x) const override {
    Vec3 g = Vec3::Zero();
    switch (kind_) {
      case One: break;
      case Linear: g = Vec3(1, 2, 3); break;
      case Quadratic: g = Vec3(1 + 2 * x[0] + 2 * x[1] + x[2], -1 + 2 * x[0] + 6 * x[1], -2 * x[2] + x[0]); break;
      case OnePlusR2: g = 2 * x; break;
    }
    for (int k = dim; k < 3; ++k) g[k] = 0;
    return g;
  }
  Real laplacian(const Vec3&) const override {
    switch (kind_) {
      case One:
      case Linear: return 0;
      case Quadratic: return 2 + (dim > 1 ? 6 : 0) + (dim > 2 ? -2 : 0);
      case OnePlusR2: return 2.0 * dim;
    }
    return 0;
  }
  std::unique_ptr<ScalarFunction> clone() const override { return std::make_unique<Polynomial>(*this); }

 private:
  Kind kind_;
};

class ExpX final : public ScalarFunction {
 public:
  explicit ExpX(int d) { dim = d; }
  std::string name() const override { return "exp-x"; }
  Real value(const Vec3& x) const override { return std::exp(x[0]); }
  Vec3 gradient(const Vec3& x) const override { return Vec3(std::exp(x[0]), 0, 0); }
  Real laplacian(const Vec3& x) const override { return std::exp(x[0]); }
  std::unique_ptr<ScalarFunction> clone() const override { return std::make_unique<ExpX>(*this); }
};
}  // namespace

const std::vector<FunctionEntry>& function_catalogue() {
  static const std::vector<FunctionEntry> list = {
      {"cos-pi", "prod_k cos(pi x_k)  ([QW] §6 test function)"},
      {"sin-pi", "prod_k sin(pi x_k)  ([QW] Example 5 solution)"},
      {"exp-x", "exp(x)  ([AAR] §5)"},
      {"one-plus-r2", "1 + |x|^2  ([QW] Example 5 coefficient)"},
      {"one", "1"},
      {"linear", "1 + x + 2y + 3z"},
      {"quadratic", "1 + x - y + x^2 + 2xy + 3y^2 - z^2 + xz"},
  };
  return list;
}

std::unique_ptr<ScalarFunction> make_function(const std::string& name, int dim) {
  check<ConfigError>(dim >= 1 && dim <= 3, "function dimension must be 1, 2 or 3, got ", dim);
  if (name == "cos-pi") return std::make_unique<ProductTrig>(true, dim);
  if (name == "sin-pi") return std::make_unique<ProductTrig>(false, dim);
  if (name == "exp-x") return std::make_unique<ExpX>(dim);
  if (name == "one-plus-r2") return std::make_unique<Polynomial>(Polynomial::OnePlusR2, dim);
  if (name == "one") return std::make_unique<Polynomial>(Polynomial::One, dim);
  if (name == "linear") return std::make_unique<Polynomial>(Polynomial::Linear, dim);
  if (name == "quadratic") return std::make_unique<Polynomial>(Polynomial::Quadratic, dim);
  std::string known;
  for (const auto& e : function_catalogue()) known += (known.empty() ? "" : ", ") + e.name;
  throw ConfigError("unknown function '" + name + "' (known: " + known + ")");
}

namespace {
class ExpressionFunction final : public ScalarFunction {
 public:
  ExpressionFunction(const std::string& u, int d, const std::vector<std::string>& grad, const std::string& lap)
      : u_(u), grad_text_(grad), lap_text_(lap) {
    dim = d;
    check<InputError>(grad.empty() || static_cast<int>(grad.size()) == d, "expected ", d,
                      " gradient expressions, got ", grad.size(), " (dimension mismatch)");
    for (const auto& g : grad) grad_.emplace_back(g);
    if (!lap.empty()) lap_ = std::make_unique<Expression>(lap);
  }
  std::string name() const override { return u_.text(); }
  Real value(const Vec3& x) const override { return u_(x); }
  Vec3 gradient(const Vec3& x) const override {
    if (grad_.empty()) return ScalarFunction::gradient(x);
    Vec3 g = Vec3::Zero();
    for (int k = 0; k < dim; ++k) g[k] = grad_[static_cast<std::size_t>(k)](x);
    return g;
  }
  Real laplacian(const Vec3& x) const override { return lap_ ? (*lap_)(x) : ScalarFunction::laplacian(x); }
  // A parser binds its variables to its own storage: a copy is parsed afresh.
  std::unique_ptr<ScalarFunction> clone() const override {
    auto copy = std::make_unique<ExpressionFunction>(u_.text(), dim, grad_text_, lap_text_);
    copy->length_scale = length_scale;
    return copy;
  }

 private:
  Expression u_;
  std::vector<std::string> grad_text_;
  std::string lap_text_;
  std::vector<Expression> grad_;
  std::unique_ptr<Expression> lap_;
};
}  // namespace

std::unique_ptr<ScalarFunction> make_expression_function(const std::string& u, int dim,
                                                         const std::vector<std::string>& gradient,
                                                         const std::string& laplacian) {
  check<ConfigError>(dim >= 1 && dim <= 3, "function dimension must be 1, 2 or 3, got ", dim);
  return std::make_unique<ExpressionFunction>(u, dim, gradient, laplacian);
}

std::unique_ptr<ScalarFunction> make_function_or_expression(const std::string& spec, int dim) {
  for (const auto& e : function_catalogue())
    if (e.name == spec) return make_function(spec, dim);
  return make_expression_function(spec, dim);
}

Real DivAGradOf::value(const Vec3& x) const { return exact_operator(OperatorKind::DivAGrad, u_, &a_, x, 0); }

std::unique_ptr<ScalarFunction> DivAGradOf::clone() const {
  std::shared_ptr<const ScalarFunction> u = u_.clone(), a = a_.clone();
  if (!u || !a) return nullptr;
  auto copy = std::unique_ptr<ScalarFunction>(new DivAGradOf(std::move(u), std::move(a)));
  copy->length_scale = length_scale;
  return copy;
}

Real second_derivative(const ScalarFunction& u, const Vec3& x, int k) {
  const Real h = 1e-3 * std::max<Real>(u.length_scale, std::abs(x[k]));
  Vec3 p = x;
  const auto at = [&](Real t) {
    p[k] = x[k] + t * h;
    return u.value(p);
  };
  return (-at(2) + 16 * at(1) - 30 * at(0) + 16 * at(-1) - at(-2)) / (12 * h * h);
}

Real DivMGradOf::value(const Vec3& x) const {
  const Vec3 gu = u_.gradient(x);
  Real f = 0;
  for (int k = 0; k < dim; ++k) {
    const ScalarFunction& m = *m_[static_cast<std::size_t>(k)];
    f += m.gradient(x)[k] * gu[k] + m.value(x) * second_derivative(u_, x, k);
  }
  return f;
}

std::unique_ptr<ScalarFunction> DivMGradOf::clone() const {
  std::shared_ptr<const ScalarFunction> u = u_.clone();
  if (!u) return nullptr;
  std::vector<std::shared_ptr<const ScalarFunction>> owned{u};
  std::vector<const ScalarFunction*> m;
  for (const ScalarFunction* mk : m_) {
    std::shared_ptr<const ScalarFunction> c = mk->clone();
    if (!c) return nullptr;
    m.push_back(c.get());
    owned.push_back(std::move(c));
  }
  auto out = std::make_unique<DivMGradOf>(*u, std::move(m));
  out->owned_ = std::move(owned);
  out->length_scale = length_scale;
  return out;
}

namespace {
// Below this many particles the copies cost more than the threads save.
constexpr Index parallel_sampling_threshold = 4096;

// body(fs, i) for every particle i, where fs are the functions (nullptr entries allowed)
// or, on other threads, clones of them. Serial if one cannot be cloned or the cloud is
// small. Each value depends only on its particle, so the result does not depend on the
// thread count; of the exceptions thrown, the one of the lowest particle index is
// rethrown (the one a serial loop would have met first).
template <class Body>
void for_each_sample(std::vector<const ScalarFunction*> fs, Index n, Body body) {
  bool cloneable = n >= parallel_sampling_threshold;
  for (const ScalarFunction* f : fs)
    if (f && cloneable) cloneable = f->clone() != nullptr;
  if (!cloneable) {
    for (Index i = 0; i < n; ++i) body(fs, i);
    return;
  }
  detail::FirstFailure failure;
#pragma omp parallel
  {
    std::vector<std::unique_ptr<ScalarFunction>> own;
    std::vector<const ScalarFunction*> mine = fs;
#ifdef _OPENMP
    if (omp_get_thread_num() != 0)
      for (auto& f : mine)
        if (f) f = own.emplace_back(f->clone()).get();
#endif
    bool failed = false;  // this thread's first failure is its lowest index (static schedule)
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (failed) continue;
      try {
        body(mine, i);
      } catch (...) {
        failure.record(i);
        failed = true;
      }
    }
  }
  failure.rethrow();
}
}  // namespace

Field sample(const ScalarFunction& u, const PointCloud& cloud) {
  Field out(cloud.size());
  for_each_sample({&u}, cloud.size(), [&](const std::vector<const ScalarFunction*>& f, Index i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    out[i] = f[0]->value(x);
    check<InputError>(std::isfinite(out[i]), "function '", printable(u.name(), 200), "' is not finite (", out[i], ") at particle ", i,
                      " (", x[0], ", ", x[1], ", ", x[2], ")");
  });
  return out;
}

Field sample(const ScalarFunction& u, const PointCloud& cloud, const std::string& role) {
  try {
    return sample(u, cloud);
  } catch (const InputError& e) {
    throw InputError(role + ": " + e.what());
  }
}

Eigen::MatrixXd sample_gradient(const ScalarFunction& u, const PointCloud& cloud) {
  Eigen::MatrixXd out(cloud.size(), cloud.dim);
  for_each_sample({&u}, cloud.size(), [&](const std::vector<const ScalarFunction*>& f, Index i) {
    const Vec3 g = f[0]->gradient(cloud.positions[static_cast<std::size_t>(i)]);
    for (int c = 0; c < cloud.dim; ++c) out(i, c) = g[c];
  });
  return out;
}

namespace {
// ∂_b ∂_c u at x: fourth-order central differences of the gradient's component c along b (step
// 1e-3 of max(length_scale, |x_b|), as the gradient's own differences: truncation ~1e-12 |u^(5)|).
Real second_derivative(const ScalarFunction& u, const Vec3& x, std::pair<int, int> axes) {
  const int b = axes.first, c = axes.second;  // (not a structured binding: clang 14 cannot capture one)
  const Real e = 1e-3 * std::max<Real>(u.length_scale, std::abs(x[b]));
  auto g = [&](Real t) {
    Vec3 y = x;
    y[b] += t;
    return u.gradient(y)[c];
  };
  return (-g(2 * e) + 8 * g(e) - 8 * g(-e) + g(-2 * e)) / (12 * e);
}
}  // namespace

Real exact_operator(OperatorKind kind, const ScalarFunction& u, const ScalarFunction* a, const Vec3& x, int component) {
  switch (kind) {
    case OperatorKind::Value: return u.value(x);
    case OperatorKind::Dx: return u.gradient(x)[0];
    case OperatorKind::Dy: return u.gradient(x)[1];
    case OperatorKind::Dz: return u.gradient(x)[2];
    case OperatorKind::Gradient: return u.gradient(x)[component];
    case OperatorKind::Laplacian: return u.laplacian(x);
    case OperatorKind::Hessian: return second_derivative(u, x, hessian_axes(component, u.dim));
    case OperatorKind::DivAGrad:
      check<ConfigError>(a != nullptr, "exact div(a grad u) needs the coefficient a");
      return a->value(x) * u.laplacian(x) + a->gradient(x).dot(u.gradient(x));
  }
  return 0;
}

Eigen::MatrixXd sample_exact(OperatorKind kind, const ScalarFunction& u, const ScalarFunction* a, const PointCloud& cloud) {
  const int nc = components(kind, cloud.dim);
  Eigen::MatrixXd out(cloud.size(), nc);
  for_each_sample({&u, a}, cloud.size(), [&](const std::vector<const ScalarFunction*>& f, Index i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int c = 0; c < nc; ++c) {
      out(i, c) = exact_operator(kind, *f[0], f[1], x, c);
      check<InputError>(std::isfinite(out(i, c)), "exact ", to_string(kind), " of '", printable(u.name(), 200), "' is not finite at particle ",
                        i, " (", x[0], ", ", x[1], ", ", x[2], ")");
    }
  });
  return out;
}

}  // namespace vrsph
