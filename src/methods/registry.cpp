#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/sph/sph.hpp>
#include <vrsph/methods/vrsph/vrsph.hpp>

namespace vrsph {

void MethodRegistry::add(MethodInfo info, MethodFactory factory) {
  for (const auto& e : entries_)
    check<ConfigError>(e.first.name != info.name, "method ", info.name, " registered twice");
  entries_.emplace_back(std::move(info), std::move(factory));
}

const MethodInfo& MethodRegistry::info(const std::string& name) const {
  std::string known;
  for (const auto& e : entries_) {
    if (e.first.name == name) return e.first;
    known += (known.empty() ? "" : ", ") + e.first.name;
  }
  throw ConfigError("unknown method '" + name + "' (known: " + known + ")");
}

std::unique_ptr<Method> MethodRegistry::create(const std::string& name, const MethodOptions& options) const {
  const MethodInfo& i = info(name);
  for (const auto& e : entries_)
    if (&e.first == &i) {
      auto m = e.second(options);
      options.reject_unused(name);
      return m;
    }
  throw ConfigError("unknown method '" + name + "'");
}

std::vector<MethodInfo> MethodRegistry::list() const {
  std::vector<MethodInfo> out;
  for (const auto& e : entries_) out.push_back(e.first);
  return out;
}

void register_builtin_methods(MethodRegistry& r) {
  r.add(sph_info(), make_sph);
  r.add(vrsph_info(), make_vrsph);
}

const MethodRegistry& builtin_methods() {
  static const MethodRegistry registry = [] {
    MethodRegistry r;
    register_builtin_methods(r);
    return r;
  }();
  return registry;
}

}  // namespace vrsph
