// SPDX-License-Identifier: BSD-3-Clause
// CLI parsing helpers: comma-separated lists, method options, seeds, and the checks that reject options that do not apply.
#include "cli_common.hpp"
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/methods/registry.hpp>

namespace vrsph::cli {


std::vector<int> parse_int_list(const std::string& text, const std::string& option) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto v = parse_integer(item);
    check<ConfigError>(v.has_value(), "option ", option, ": '", printable(item), "' is not an integer");
    check<ConfigError>(*v >= 1 && *v <= 100000000, "option ", option, ": ", *v, " is out of range (1 to 100000000)");
    out.push_back(static_cast<int>(*v));
  }
  check<ConfigError>(!out.empty(), "option ", option, " needs at least one value");
  return out;
}

std::vector<std::string> parse_name_list(const std::string& text, const std::string& option) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    check<ConfigError>(!item.empty(), "option ", option, ": empty name in '", text, "'");
    out.push_back(item);
  }
  check<ConfigError>(!out.empty(), "option ", option, " needs at least one name");
  return out;
}

std::vector<double> parse_real_list(const std::string& text, const std::string& option) {
  std::vector<double> out;
  for (const auto& item : parse_name_list(text, option)) {
    const auto v = parse_real(item);
    check<ConfigError>(v.has_value(), "option ", option, ": '", printable(item), "' is not a number");
    check<ConfigError>(std::isfinite(*v), "option ", option, ": '", printable(item), "' is not finite");
    out.push_back(*v);
  }
  return out;
}

std::vector<std::string> parse_expression_list(const std::string& text, const std::string& option) {
  std::vector<std::string> out{""};
  int depth = 0;
  for (char c : text) {
    depth += c == '(' ? 1 : c == ')' ? -1 : 0;
    check<ConfigError>(depth >= 0, "option ", option, ": unbalanced ')' in '", printable(text), "'");
    if (c == ',' && depth == 0) out.emplace_back();
    else out.back() += c;
  }
  check<ConfigError>(depth == 0, "option ", option, ": unbalanced '(' in '", printable(text), "'");
  for (const auto& e : out)
    check<ConfigError>(e.find_first_not_of(" \t") != std::string::npos, "option ", option, ": empty expression in '",
                       printable(text), "'");
  return out;
}

std::map<std::string, MethodOptions> parse_method_options(const std::vector<std::string>& items,
                                                          const std::vector<std::string>& methods) {
  std::map<std::string, MethodOptions> out;
  for (const auto& item : items) {
    const auto colon = item.find(':'), eq = item.find('=');
    const bool scoped = colon != std::string::npos && colon < eq;
    const std::string target = scoped ? item.substr(0, colon) : "";
    check<ConfigError>(!scoped || std::find(methods.begin(), methods.end(), target) != methods.end(), "--method-opt ",
                       item, ": method ", target, " is not in --method");
    const MethodOptions parsed = MethodOptions::parse({scoped ? item.substr(colon + 1) : item});
    for (const auto& m : methods)
      if (!scoped || m == target)
        for (const auto& [k, v] : parsed.values()) out[m].set(k, v);
  }
  return out;
}

void reject_group_options(const CLI::App& cmd, const std::string& group, const std::string& applies_to) {
  for (const auto* o : cmd.get_options())
    check<ConfigError>(o->get_group() != group || o->count() == 0, o->get_name(), " applies to ", applies_to, " only");
}

void reject_empty_values(const CLI::App& command) {
  for (const CLI::Option* opt : command.get_options())
    for (const std::string& value : opt->results())
      check<ConfigError>(!value.empty() || opt->get_type_size() == 0, "option ", opt->get_name(),
                         " was given an empty value");
  for (const CLI::App* sub : command.get_subcommands()) reject_empty_values(*sub);
}

void reject_output_over_input(const CLI::App& command) {
  // Options that name files vrsph reads, and files it writes (--vtu-series is a prefix: its
  // collection PREFIX.pvd is what could coincide with an input).
  static const std::vector<std::string> inputs = {"--input", "--cloud-file", "--geometry", "--config", "--at",
                                                   "--perm-file", "--anchor-script"};
  static const std::vector<std::pair<std::string, std::string>> outputs = {
      {"--output", ""}, {"--plot", ""}, {"--vtu", ""}, {"--history", ""}, {"--krylov-output", ""},
      {"--profile", ""}, {"--vtu-series", ".pvd"}};
  const auto value = [&](const std::string& name) -> std::string {
    for (const CLI::Option* opt : command.get_options())
      if (opt->check_lname(name.substr(2)) && !opt->results().empty()) return opt->results().back();
    return "";
  };
  for (const auto& [out, suffix] : outputs) {
    const std::string written = value(out);
    if (written.empty()) continue;
    for (const auto& in : inputs) check_output_is_not_input(written + suffix, value(in), out);
  }
  for (const CLI::App* sub : command.get_subcommands()) reject_output_over_input(*sub);
}

void check_h_knn_applies(const CLI::Option* h_knn, const std::string& h_mode) {
  check<ConfigError>(h_knn->count() == 0 || h_mode == "knn", "--h-knn applies only with --h-mode knn (got --h-mode ",
                     h_mode, ")");
}

CLI::Validator seed_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto v = parse_integer(text);
        return v && *v >= 0 ? std::string() : "a seed is a non-negative integer, got '" + printable(text) + "'";
      },
      "SEED");
}

CLI::Validator boolean_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        // Any case: CLI11 itself reads "TRUE" as true.
        if (parse_boolean(to_lower(text))) return {};
        return "expected 1/0, true/false, on/off or yes/no, got '" + printable(text) + "'";
      },
      "");  // the option's type already reads BOOLEAN in --help
}

}  // namespace vrsph::cli
