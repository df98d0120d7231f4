// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The method registry: name -> factory, filled by one explicit list
// (register_builtin_methods, PETSc itregis.c style) and looked up at run time.
#include <functional>
#include <memory>
#include <vrsph/methods/method.hpp>

namespace vrsph {

using MethodFactory = std::function<std::unique_ptr<Method>(const MethodOptions&)>;

class MethodRegistry {
 public:
  void add(MethodInfo info, MethodFactory factory);
  /// Throws ConfigError for an unknown name (listing the known ones) or unknown options.
  std::unique_ptr<Method> create(const std::string& name, const MethodOptions& options = {}) const;
  const MethodInfo& info(const std::string& name) const;
  std::vector<MethodInfo> list() const;

 private:
  std::vector<std::pair<MethodInfo, MethodFactory>> entries_;
};

/// Registers every built-in method; the one place that lists them.
void register_builtin_methods(MethodRegistry& registry);
/// The registry with every built-in method (built once).
const MethodRegistry& builtin_methods();

}  // namespace vrsph
