// SPDX-License-Identifier: BSD-3-Clause
// `vrsph methods` and `vrsph kernels`: what the registry and the kernel catalogue hold.
#include <iostream>
#include <string_view>
#include <vector>
#include <vrsph/io/json.hpp>
#include <vrsph/core/references.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/registry.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"

namespace vrsph::cli {

namespace {
// The method's choice options at their defaults, "key=value ...": a method created from
// empty options has asked for each with its fallback (MethodOptions::choice_defaults).
std::string choice_defaults(const std::string& method) {
  const MethodOptions none;
  (void)builtin_methods().create(method, none);
  std::string out;
  for (const auto& [key, value] : none.choice_defaults()) out += (out.empty() ? "" : " ") + key + "=" + value;
  return out;
}

Json to_json(const Reference& r) {
  return Json::object({{"key", r.key},
                       {"authors", r.authors},
                       {"title", r.title},
                       {"venue", r.venue},
                       {"year", r.year},
                       {"identifier", r.identifier},
                       {"citation", r.citation()}});
}

// "Qiao & Wei 2025 (arXiv:2503.15188)" per publication the method cites: a table cell.
std::string short_references(const MethodInfo& m) {
  std::string out;
  for (const Reference& r : references_cited_in(m.source)) {
    std::vector<std::string> surnames;  // "Z. Qiao, Y. Wei" -> Qiao, Wei
    std::string_view rest = r.authors;
    while (!rest.empty()) {
      const std::size_t comma = rest.find(", ");
      const std::string_view name = rest.substr(0, comma);
      surnames.emplace_back(name.substr(name.rfind(' ') == std::string_view::npos ? 0 : name.rfind(' ') + 1));
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 2);
    }
    const std::string who = surnames.size() == 1   ? surnames[0]
                            : surnames.size() == 2 ? surnames[0] + " & " + surnames[1]
                                                   : surnames[0] + " et al.";
    out += (out.empty() ? "" : "; ") + who + " " + std::to_string(r.year);
    if (!r.identifier.empty()) out += " (" + std::string(r.identifier.substr(0, r.identifier.find(','))) + ")";
  }
  return out;
}
}  // namespace

void add_methods_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("methods", "List the registered methods (name, source and reference, operators, claimed order)");
  auto format = std::make_shared<std::string>("md");
  cmd->add_option("--format", *format, "Output format: md, csv or json")->capture_default_str();
  cmd->callback([format] {
    const auto methods = builtin_methods().list();
    if (*format == "json") {
      // A plain JSON list of method objects.
      auto list = Json::array();
      for (const auto& m : methods) {
        Json o;
        o["name"] = m.name;
        // `reference`: the publication the method comes from (the first one its source cites);
        // `references`: every publication it cites, that one first.
        const auto cited = references_cited_in(m.source);
        o["source"] = m.source;
        o["reference"] = cited.empty() ? Json() : to_json(cited.front());
        auto all = Json::array();
        for (const Reference& r : cited) all.push_back(to_json(r));
        o["references"] = all;
        o["description"] = m.description;
        o["claimed_order"] = m.claimed_order;
        auto ops = Json::array();
        for (auto k : m.provided()) ops.push_back(std::string(to_string(k)));
        o["operators"] = ops;
        auto opts = Json::object();
        for (const auto& [k, v] : m.options) opts[k] = v;
        o["options"] = opts;
        auto profiles = Json::object();
        for (const auto& [k, v] : m.profiles) profiles[k] = v;
        o["profiles"] = profiles;
        o["defaults"] = choice_defaults(m.name);
        list.push_back(o);
      }
      std::cout << list.dump(2) << '\n';
      return;
    }
    Table t;
    t.columns = {"name", "source", "reference", "operators", "claimed order", "defaults", "profiles"};
    for (const auto& m : methods) {
      std::string ops, profiles;
      const std::string defaults = choice_defaults(m.name);
      for (auto k : m.provided()) ops += (ops.empty() ? "" : " ") + std::string(to_string(k));
      for (const auto& [name, what] : m.profiles) profiles += (profiles.empty() ? "" : " | ") + name + ": " + what;
      t.add_row({{"name", m.name}, {"source", m.source}, {"reference", short_references(m)}, {"operators", ops}, {"claimed order", m.claimed_order},
                 {"defaults", defaults}, {"profiles", profiles}});
    }
    std::cout << format_table(t, parse_table_format(*format));
  });
}

void add_kernels_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("kernels", "List the smoothing kernels and their normalisation constants");
  auto format = std::make_shared<std::string>("md");
  cmd->add_option("--format", *format, "Output format: md, csv or json")->capture_default_str();
  cmd->callback([format] {
    Table t;
    t.columns = {"name", "description", "support/smoothing_length", "sigma_1", "sigma_2", "sigma_3"};
    for (const auto& k : kernel_catalogue())
      t.add_row({{"name", std::string(k.name)},
                 {"description", std::string(k.description)},
                 {"support/smoothing_length", k.support_per_smoothing_length},
                 {"sigma_1", Kernel(k.type, 1, 1.0).normalisation()},
                 {"sigma_2", Kernel(k.type, 2, 1.0).normalisation()},
                 {"sigma_3", Kernel(k.type, 3, 1.0).normalisation()}});
    std::cout << format_table(t, parse_table_format(*format));
  });
}

}  // namespace vrsph::cli
