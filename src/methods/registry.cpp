// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/aar/modified_fpm.hpp>
#include <vrsph/methods/aar/nested.hpp>
#include <vrsph/methods/gpm/gpm.hpp>
#include <vrsph/methods/gpm/mps.hpp>
#include <vrsph/methods/sph/sph.hpp>
#include <vrsph/methods/spe/spe.hpp>
#include <vrsph/methods/taylor/cspm.hpp>
#include <vrsph/methods/taylor/fpm.hpp>
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
  r.add(fpm_info(), make_fpm);
  r.add(cspm_info(), make_cspm);
  r.add(kgf_info(), make_kgf);
  r.add(aar_sph_info(), make_aar_sph);
  r.add(chen_beraun_info(), make_chen_beraun);
  r.add(rkpm1_info(), make_rkpm1);
  r.add(rkpm2_info(), make_rkpm2);
  r.add(mfpm_info(), make_mfpm);
  r.add(fpm2o_info(), make_fpm2o);
  r.add(brookshaw_info(), make_brookshaw);
  r.add(cb_sph_info(), make_cb_sph);
  r.add(s_sph_info(), make_s_sph);
  r.add(m_sph_info(), make_m_sph);
  r.add(gpm_info(), make_gpm);
  r.add(mps_info(), make_mps);
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
