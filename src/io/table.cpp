// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <variant>
#include <vrsph/core/error.hpp>
#include <vrsph/io/table.hpp>

namespace vrsph {

void Table::add_row(const std::vector<std::pair<std::string, TableCell>>& cells) {
  std::vector<TableCell> row(columns.size());
  for (const auto& [name, value] : cells) {
    auto it = std::find(columns.begin(), columns.end(), name);
    check<ConfigError>(it != columns.end(), "table has no column '", name, "'");
    row[static_cast<std::size_t>(it - columns.begin())] = value;
  }
  rows.push_back(std::move(row));
}

TableFormat parse_table_format(const std::string& name) {
  if (name == "md" || name == "markdown") return TableFormat::Markdown;
  if (name == "csv") return TableFormat::Csv;
  if (name == "json") return TableFormat::Json;
  throw ConfigError("unknown output format '" + name + "' (expected md, csv or json)");
}

namespace {
std::string text(const TableCell& c) {
  std::ostringstream os;
  if (std::holds_alternative<long long>(c)) os << std::get<long long>(c);
  else if (std::holds_alternative<double>(c)) {
    const double v = std::get<double>(c);
    if (std::isnan(v)) os << "–";
    else {
      os.precision(4);
      os << std::scientific << v;
    }
  } else if (std::holds_alternative<std::string>(c)) os << std::get<std::string>(c);
  else if (std::holds_alternative<bool>(c)) os << (std::get<bool>(c) ? "yes" : "no");
  return os.str();
}
std::string csv_text(const TableCell& c) {
  if (std::holds_alternative<double>(c)) {
    std::ostringstream os;
    os.precision(10);
    const double v = std::get<double>(c);
    if (!std::isnan(v)) os << v;
    return os.str();
  }
  return text(c);
}
}  // namespace

std::string to_markdown(const Table& t) {
  std::ostringstream os;
  os << '|';
  for (const auto& c : t.columns) os << ' ' << c << " |";
  os << "\n|";
  for (std::size_t k = 0; k < t.columns.size(); ++k) os << "---|";
  os << '\n';
  for (const auto& r : t.rows) {
    os << '|';
    for (const auto& c : r) os << ' ' << text(c) << " |";
    os << '\n';
  }
  return os.str();
}

std::string csv_header(const Table& t) {
  std::string line;
  for (std::size_t k = 0; k < t.columns.size(); ++k) {
    if (k) line += ',';
    line += t.columns[k];
  }
  line += '\n';
  return line;
}

std::string csv_row(const std::vector<TableCell>& row) {
  std::string line;
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (k) line += ',';
    line += csv_text(row[k]);
  }
  line += '\n';
  return line;
}

std::string to_csv(const Table& t) {
  std::string out = csv_header(t);
  for (const auto& r : t.rows) out += csv_row(r);
  return out;
}

Json json_cell(const TableCell& c) {
  return std::visit(
      [](const auto& v) {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::monostate>) return Json();
        else return Json(v);  // a NaN is null: JSON has none (first-row orders)
      },
      c);
}

Json json_rows(const Table& t) {
  Json rows = Json::array();
  for (const auto& r : t.rows) {
    Json o = Json::object();
    for (std::size_t k = 0; k < r.size(); ++k) o[t.columns[k]] = json_cell(r[k]);
    rows.push_back(std::move(o));
  }
  return rows;
}

std::string to_json(const Table& t, const Json& extra) {
  Json j = Json::object();
  j.merge(extra);
  j["rows"] = json_rows(t);
  return j.dump(2) + "\n";
}

std::string format_table(const Table& t, TableFormat f, const Json& extra) {
  switch (f) {
    case TableFormat::Markdown: return to_markdown(t);
    case TableFormat::Csv: return to_csv(t);
    case TableFormat::Json: return to_json(t, extra);
  }
  return {};
}

}  // namespace vrsph
