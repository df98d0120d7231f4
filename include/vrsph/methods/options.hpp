// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// MethodOptions: the per-method knobs (key=value strings from the CLI or a config
// file). Each method reads its keys with typed getters and defaults next to the
// code that uses them; keys that no getter asked for are an error (typos must not
// be silently ignored).
#include <map>
#include <set>
#include <string>
#include <vrsph/core/types.hpp>

namespace vrsph {

class MethodOptions {
 public:
  MethodOptions() = default;
  /// Parses "key=value" items; throws ConfigError on a malformed item or a repeated key.
  static MethodOptions parse(const std::vector<std::string>& items);
  void set(const std::string& key, const std::string& value) { values_[key] = value; }

  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// Value must be one of `allowed`; throws ConfigError otherwise.
  std::string get_choice(const std::string& key, const std::string& fallback, const std::set<std::string>& allowed) const;
  /// A finite number; throws ConfigError for text that is not one, NaN or infinity.
  Real get_real(const std::string& key, Real fallback) const;
  /// An integer in [min, max] written in digits; throws ConfigError otherwise ("1e30" too).
  long long get_int(const std::string& key, long long fallback, long long min, long long max) const;
  bool get_bool(const std::string& key, bool fallback) const;

  /// Throws ConfigError naming every key no getter has read (call after construction).
  void reject_unused(const std::string& method) const;
  const std::map<std::string, std::string>& values() const { return values_; }
  /// The fallback of every get_choice call so far, by key: a method created from empty
  /// options has thereby listed its defaults (`vrsph methods`).
  const std::map<std::string, std::string>& choice_defaults() const { return choice_defaults_; }

 private:
  std::map<std::string, std::string> values_;
  mutable std::set<std::string> used_;
  mutable std::map<std::string, std::string> choice_defaults_;
};

/// The options given for `method` in a per-method map, or the defaults (empty options).
const MethodOptions& options_for(const std::map<std::string, MethodOptions>& per_method, const std::string& method);

}  // namespace vrsph
