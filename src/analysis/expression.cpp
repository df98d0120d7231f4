// SPDX-License-Identifier: BSD-3-Clause
// Expressions in x, y, z (and t) through muParser, the optional part MUPARSER: a build
// without it refuses an expression when it is made (FeatureUnavailable).
#include <cmath>
#include <numbers>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/core/parse.hpp>
#if VRSPH_HAVE_MUPARSER
#include <muParser.h>
#endif

namespace vrsph {

struct Expression::Impl {
  std::string text;
  mutable double x = 0, y = 0, z = 0, t = 0;
#if VRSPH_HAVE_MUPARSER
  mu::Parser parser;
#endif
};

Expression::Expression(const std::string& text, bool with_time) : impl_(std::make_unique<Impl>()) {
  impl_->text = text;
  check<InputError>(!text.empty(), "empty expression");
#if !VRSPH_HAVE_MUPARSER
  (void)with_time;
  require_part("MUPARSER", "the expression '" + printable(text, 200) + "'");
#else
  try {
    auto& p = impl_->parser;
    p.DefineVar("x", &impl_->x);
    p.DefineVar("y", &impl_->y);
    p.DefineVar("z", &impl_->z);
    if (with_time) p.DefineVar("t", &impl_->t);
    p.DefineConst("pi", std::numbers::pi);
    p.DefineConst("e", std::numbers::e);
    p.SetExpr(text);
    (void)p.Eval();  // parse now, so errors surface here and not mid-run
  } catch (const mu::Parser::exception_type& e) {
    throw InputError("cannot parse expression '" + printable(text, 200) + "': " + e.GetMsg());
  }
#endif
}
Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
const std::string& Expression::text() const { return impl_->text; }

Real Expression::operator()(const Vec3& x, Real t) const {
  impl_->t = t;
  return (*this)(x);
}

Real Expression::operator()(const Vec3& x) const {
  impl_->x = x[0];
  impl_->y = x[1];
  impl_->z = x[2];
#if VRSPH_HAVE_MUPARSER
  try {
    return impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError("cannot evaluate expression '" + printable(impl_->text, 200) + "': " + e.GetMsg());
  }
#else
  return std::nan("");  // not reached: the constructor refused
#endif
}

}  // namespace vrsph
