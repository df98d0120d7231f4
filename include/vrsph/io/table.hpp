// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A small result table shared by the CLI and the tests, written as Markdown,
// CSV or JSON ({"rows":[{column: value, ...}], ...extra keys}).
#include <map>
#include <string>
#include <variant>
#include <vector>
#include <vrsph/io/json.hpp>

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
/// to_csv's lines one at a time (a table written as it grows): the header, and one row.
std::string csv_header(const Table& t);
std::string csv_row(const std::vector<TableCell>& row);
/// One cell as a JSON value: an empty cell or a NaN is null.
Json json_cell(const TableCell& c);
/// The rows as a JSON array of objects {column: json_cell}.
Json json_rows(const Table& t);
/// {...extra's members, "rows": json_rows(t)}: extra (e.g. problem metadata) is an object or
/// null; throws ConfigError otherwise.
std::string to_json(const Table& t, const Json& extra = {});
std::string format_table(const Table& t, TableFormat f, const Json& extra = {});
// A JSON text as `extra` would become one string value, not merged members: build a Json.
std::string to_json(const Table&, const char*) = delete;
std::string to_json(const Table&, const std::string&) = delete;
std::string format_table(const Table&, TableFormat, const char*) = delete;
std::string format_table(const Table&, TableFormat, const std::string&) = delete;

}  // namespace vrsph
