// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <cstdlib>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/methods/options.hpp>

namespace vrsph {

MethodOptions MethodOptions::parse(const std::vector<std::string>& items) {
  MethodOptions o;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    check<ConfigError>(eq != std::string::npos && eq > 0, "method option '", printable(item),
                       "' is not of the form key=value");
    const std::string key = item.substr(0, eq);
    check<ConfigError>(!o.values_.count(key), "method option '", printable(key), "' given twice");
    o.values_[key] = item.substr(eq + 1);
  }
  return o;
}

std::string MethodOptions::get_string(const std::string& key, const std::string& fallback) const {
  used_.insert(key);
  const auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

std::string MethodOptions::get_choice(const std::string& key, const std::string& fallback,
                                      const std::set<std::string>& allowed) const {
  choice_defaults_.emplace(key, fallback);
  const std::string v = get_string(key, fallback);
  if (!allowed.count(v)) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw ConfigError(detail::concat("method option ", key, "='", printable(v), "' is not one of: ", list));
  }
  return v;
}

Real MethodOptions::get_real(const std::string& key, Real fallback) const {
  const auto it = values_.find(key);
  used_.insert(key);
  if (it == values_.end()) return fallback;
  const auto v = parse_real(it->second);
  check<ConfigError>(v.has_value(), "method option ", key, "='", printable(it->second), "' is not a number");
  check<ConfigError>(std::isfinite(*v), "method option ", key, "='", printable(it->second), "' is not finite");
  return *v;
}

long long MethodOptions::get_int(const std::string& key, long long fallback, long long min, long long max) const {
  const auto it = values_.find(key);
  used_.insert(key);
  if (it == values_.end()) return fallback;
  const auto v = parse_integer(it->second);
  check<ConfigError>(v.has_value(), "method option ", key, "='", printable(it->second),
                     "' is not an integer (digits only, e.g. ", min, ")");
  check<ConfigError>(*v >= min && *v <= max, "method option ", key, "=", *v, " is out of range (", min, " to ", max,
                     ")");
  return *v;
}

bool MethodOptions::get_bool(const std::string& key, bool fallback) const {
  const std::string v = get_string(key, fallback ? "true" : "false");
  if (const std::optional<bool> b = parse_boolean(v)) return *b;
  throw ConfigError(detail::concat("method option ", key, "='", printable(v), "' is not a boolean"));
}

void MethodOptions::reject_unused(const std::string& method) const {
  std::string unknown;
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) unknown += (unknown.empty() ? "" : ", ") + k;
  check<ConfigError>(unknown.empty(), "method ", method, " has no option(s): ", printable(unknown));
}

const MethodOptions& options_for(const std::map<std::string, MethodOptions>& per_method, const std::string& method) {
  static const MethodOptions defaults;
  const auto it = per_method.find(method);
  return it == per_method.end() ? defaults : it->second;
}

}  // namespace vrsph
