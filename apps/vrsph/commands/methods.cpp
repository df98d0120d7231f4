// `vrsph methods` and `vrsph kernels`: what the registry and the kernel catalogue hold.
#include <iostream>
#include <nlohmann/json.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/registry.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"

namespace vrsph::cli {

void add_methods_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("methods", "List the registered methods (name, paper, operators, claimed order)");
  auto format = std::make_shared<std::string>("md");
  cmd->add_option("--format", *format, "Output format: md, csv or json")->capture_default_str();
  cmd->callback([format] {
    const auto methods = builtin_methods().list();
    if (*format == "json") {
      // A plain JSON list of method objects.
      auto list = nlohmann::ordered_json::array();
      for (const auto& m : methods) {
        nlohmann::ordered_json o;
        o["name"] = m.name;
        o["paper"] = m.paper;
        o["description"] = m.description;
        o["claimed_order"] = m.claimed_order;
        auto ops = nlohmann::ordered_json::array();
        for (auto k : m.operators) ops.push_back(std::string(to_string(k)));
        o["operators"] = ops;
        auto opts = nlohmann::ordered_json::object();
        for (const auto& [k, v] : m.options) opts[k] = v;
        o["options"] = opts;
        list.push_back(o);
      }
      std::cout << list.dump(2) << '\n';
      return;
    }
    Table t;
    t.columns = {"name", "paper", "operators", "claimed order"};
    for (const auto& m : methods) {
      std::string ops;
      for (auto k : m.operators) ops += (ops.empty() ? "" : " ") + std::string(to_string(k));
      t.add_row({{"name", m.name}, {"paper", m.paper}, {"operators", ops}, {"claimed order", m.claimed_order}});
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
