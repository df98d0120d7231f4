// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/io/input_file.hpp>
#include "problem_file.hpp"
#if VRSPH_HAVE_TOML
#include <toml++/toml.h>
#endif

namespace vrsph::cli {

CLI::Option* add_config_option(CLI::App* cmd, std::string& path) {
  return cmd->add_option("--config", path,
                         "Problem file (TOML): keys are this command's long options without the dashes, tables only "
                         "group them; command-line options win; paths are relative to the file");
}

#if VRSPH_HAVE_TOML
namespace {
std::string location(const std::string& path, const toml::source_region& src) {
  return path + ":" + std::to_string(src.begin.line);
}

// A scalar TOML value as the text a command line would carry.
std::string scalar_text(const toml::node& v, const std::string& where, const std::string& key) {
  if (const auto* s = v.as_string()) return s->get();
  if (const auto* i = v.as_integer()) return std::to_string(i->get());
  if (const auto* f = v.as_floating_point()) {
    std::ostringstream os;
    os.precision(17);
    os << f->get();
    return os.str();
  }
  if (const auto* b = v.as_boolean()) return b->get() ? "true" : "false";
  std::ostringstream type;
  type << v.type();
  throw ConfigError(where + ": key '" + key + "' is of type " + type.str() + "; expected a string, number or boolean");
}

struct Entry {
  std::string key, where;
  const toml::node* value;
};

// Leaf keys of the document; tables only group them.
void collect(const toml::table& t, const std::string& path, std::vector<Entry>& out) {
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (const auto* sub = v.as_table()) {
      collect(*sub, path, out);
      continue;
    }
    out.push_back({key, location(path, v.source()), &v});
  }
}
}  // namespace


namespace {
// Every option that names a file, read or written: relative to the problem file's directory.
const std::vector<std::string> kPathOptions = {"--cloud-file", "--cloud-file-pattern", "--geometry", "--output",
                                               "--plot", "--vtu", "--csv", "--perm-file", "--history",
                                               "--krylov-output", "--profile", "--at", "--vtu-series", "--input"};
}  // namespace

void apply_problem_file(CLI::App& cmd, const std::string& path) {
  std::ifstream in = open_input(path, "problem file");
  toml::table doc;
  try {
    doc = toml::parse(in, path);
  } catch (const toml::parse_error& e) {
    throw ConfigError(detail::concat(path, ":", e.source().begin.line, ":", e.source().begin.column, ": ", e.description()));
  }
  std::vector<Entry> entries;
  collect(doc, path, entries);
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  std::vector<std::string> seen;
  for (const Entry& e : entries) {
    check<ConfigError>(e.key != "config", e.where, ": a problem file cannot name another (--config)");
    check<ConfigError>(std::find(seen.begin(), seen.end(), e.key) == seen.end(), e.where, ": key '", e.key,
                       "' appears twice (in two tables)");
    seen.push_back(e.key);
    CLI::Option* opt = nullptr;
    try {
      opt = cmd.get_option("--" + e.key);
    } catch (const CLI::OptionNotFound&) {
    }
    // --help, --help-all and --version are actions, not settings: a problem file holds settings.
    const bool action = e.key == "help" || e.key == "help-all" || e.key == "version";
    check<ConfigError>(opt != nullptr && !action, e.where, ": unknown key '", e.key, "' (not an option of vrsph ",
                       cmd.get_name(), " that a problem file can set; see vrsph ", cmd.get_name(), " --help)");
    if (opt->count() > 0) continue;  // the command line wins
    const bool is_path = std::find(kPathOptions.begin(), kPathOptions.end(), "--" + e.key) != kPathOptions.end();
    auto text = [&](const toml::node& v) {
      std::string s = scalar_text(v, e.where, e.key);
      if (is_path && !s.empty() && std::filesystem::path(s).is_relative() && !base.empty()) s = (base / s).string();
      return s;
    };
    try {
      if (const auto* arr = e.value->as_array()) {
        std::vector<std::string> items;
        for (const auto& v : *arr) items.push_back(text(v));
        static const std::vector<std::string> comma_lists = {"--method", "--n", "--seeds", "--neumann", "--periodic"};
        if (opt->get_items_expected_max() > 1) {  // a repeatable option (--method-opt)
          for (auto& item : items) opt->add_result(item);
        } else if (std::find(comma_lists.begin(), comma_lists.end(), "--" + e.key) != comma_lists.end()) {
          std::string joined;
          for (const auto& item : items) joined += (joined.empty() ? "" : ",") + item;
          opt->add_result(joined);
        } else {
          throw ConfigError(detail::concat(e.where, ": key '", e.key, "' takes one value, not a list"));
        }
      } else {
        opt->add_result(text(*e.value));
      }
      opt->run_callback();
    } catch (const CLI::Error& err) {
      throw ConfigError(detail::concat(e.where, ": key '", e.key, "': ", err.what()));
    }
  }
}
#else
void apply_problem_file(CLI::App&, const std::string& path) {
  require_part("TOML", "the problem file '" + path + "' (--config)");
}
#endif

}  // namespace vrsph::cli
