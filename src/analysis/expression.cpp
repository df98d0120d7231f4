// SPDX-License-Identifier: BSD-3-Clause
// Expressions in x, y, z (and t) through muParser, the optional part MUPARSER: a build
// without it refuses an expression when it is made (FeatureUnavailable).
#include <cctype>
#include <cmath>
#include <cstdlib>
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

namespace {
// The first number written in the text that a double cannot hold (1e400): muParser reports it
// as an "unexpected token", which does not name the cause. Empty if none.
[[maybe_unused]] std::string overflowing_literal(const std::string& text) {
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  for (std::size_t k = 0; k < text.size();) {
    const bool in_name = k > 0 && (std::isalnum(at(k - 1)) || text[k - 1] == '_');  // x2, a_1e5
    if (in_name || !(std::isdigit(at(k)) || text[k] == '.')) {
      ++k;
      continue;
    }
    char* end = nullptr;
    const double value = std::strtod(text.c_str() + k, &end);  // the longest number from k
    const auto length = static_cast<std::size_t>(end - (text.c_str() + k));
    if (length == 0) {
      ++k;
      continue;
    }
    if (!std::isfinite(value)) return text.substr(k, length);
    k += length;
  }
  return {};
}
}  // namespace

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
    const std::string huge = overflowing_literal(text);
    if (!huge.empty())
      throw InputError("cannot parse expression '" + printable(text, 200) + "': the number " + printable(huge, 40) +
                       " is beyond the range of double precision (about 1.8e308)");
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
