// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A small result table shared by the CLI and the tests, written as Markdown,
// CSV or JSON ({"rows":[{column: value, ...}], ...extra keys}).
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace vrsph {

using TableCell = std::variant<std::monostate, long long, double, std::string, bool>;

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<TableCell>> rows;
  /// Appends a row; cells are matched to columns by name (missing ones are empty).
  void add_row(const std::vector<std::pair<std::string, TableCell>>& cells);
};

enum class TableFormat { Markdown, Csv, Json };
/// "md" | "markdown" | "csv" | "json"; throws ConfigError otherwise.
TableFormat parse_table_format(const std::string& name);

std::string to_markdown(const Table& t);
std::string to_csv(const Table& t);
/// extra: a JSON object text merged at top level (e.g. problem metadata); may be empty.
std::string to_json(const Table& t, const std::string& extra_json_object = "");
std::string format_table(const Table& t, TableFormat f, const std::string& extra_json_object = "");

}  // namespace vrsph
