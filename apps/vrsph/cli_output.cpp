// SPDX-License-Identifier: BSD-3-Clause
// CLI output: tables to stdout or a file, --columns, PNG plots through share/'s scripts, .pvtu names and temporary files.
#include "cli_common.hpp"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>

namespace vrsph::cli {

namespace {
// A script of share/: next to an installed binary (PREFIX/share/vrsph), else in the source tree.
std::string find_share_script(const std::string& name) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto installed = exe.parent_path().parent_path() / "share" / "vrsph" / name;
    if (std::filesystem::exists(installed)) return installed.string();
  }
  return std::string(VRSPH_SOURCE_DIR) + "/share/" + name;
}

std::string find_plot_script() {
  if (const char* env = std::getenv("VRSPH_PLOT_SCRIPT")) return env;
  return find_share_script("plot_convergence.py");
}
}  // namespace

namespace {
// Runs a plot script that reads `data` and writes the PNG given as its second argument. The
// script writes a temporary file beside `png` that replaces it only when complete.
void run_python(const std::string& script_path, const std::string& data, const std::string& png,
                const std::string& options) {
  const auto log_path = std::filesystem::temp_directory_path() / ("vrsph-plot-" + std::to_string(::getpid()) + ".log");
  write_file_via(png, "plot", [&](const std::string& temporary) {
    const std::string cmd = shell_quote(python_interpreter()) + " " + shell_quote(script_path) + " " + shell_quote(data) +
                            " " + shell_quote(temporary) + options + " 2>" + shell_quote(log_path.string());
    const int rc = std::system(cmd.c_str());
    // Our message first; of Python's traceback only its last line (the actual reason).
    std::string last, line;
    {
      std::ifstream log(log_path);
      while (std::getline(log, line))
        if (!line.empty()) last = line;
    }
    std::filesystem::remove(log_path);
    check<IoError>(rc == 0, "plotting to '", png, "' failed", last.empty() ? "" : ": " + last,
                   " (needs python3 with matplotlib: Debian's python3-matplotlib; VRSPH_PYTHON selects the interpreter)");
  });
}
}  // namespace

namespace {
std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : sep) + item;
  return out;
}

}  // namespace

void validate_columns(const OutputOptions& out, const std::vector<std::string>& available) {
  if (out.columns == "all" || out.columns == "key") return;
  for (const auto& name : parse_name_list(out.columns, "--columns"))
    check<ConfigError>(std::find(available.begin(), available.end(), name) != available.end(), "--columns: no column '",
                       name, "' (the table has: ", join(available, ", "), ")");
}

namespace {
// The table with only the columns --columns asks for (Markdown output).
Table displayed_columns(const Table& t, const OutputOptions& out) {
  if (out.columns == "all" || (out.columns == "key" && out.key_columns.empty())) return t;
  std::vector<std::string> wanted = out.key_columns;
  if (out.columns != "key") wanted = parse_name_list(out.columns, "--columns");
  Table shown;
  std::vector<std::size_t> pick;
  for (const auto& name : wanted) {
    const auto it = std::find(t.columns.begin(), t.columns.end(), name);
    if (it == t.columns.end()) {
      validate_columns(out, t.columns);  // a name the user gave: an error
      continue;                          // a key column this table lacks
    }
    shown.columns.push_back(name);
    pick.push_back(static_cast<std::size_t>(it - t.columns.begin()));
  }
  for (const auto& row : t.rows) {
    std::vector<TableCell> cells;
    for (const auto k : pick) cells.push_back(row[k]);
    shown.rows.push_back(std::move(cells));
  }
  return shown;
}
}  // namespace

void add_columns_option(CLI::App* cmd, OutputOptions& out, std::vector<std::string> key_columns) {
  out.key_columns = std::move(key_columns);
  cmd->add_option("--columns", out.columns,
                  "Markdown table columns: key (" + join(out.key_columns, ", ") +
                      "), all, or a comma-separated list (CSV and JSON always have all)")
      ->capture_default_str();
}

void run_plot_script(const std::string& script, const std::string& data, const std::string& png,
                     const std::string& options) {
  run_python(find_share_script(script), data, png, options);
}

std::string python_interpreter() {
  if (const char* env = std::getenv("VRSPH_PYTHON")) return env;
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void validate_output(const OutputOptions& out) {
  (void)parse_table_format(out.format);  // ConfigError on an unknown format
  std::error_code ec;
  check<ConfigError>(out.output.empty() || !std::filesystem::is_directory(out.output, ec), "--output '", out.output,
                     "' is a directory: give a file name");
  if (out.plot.empty()) return;
  check<ConfigError>(!std::filesystem::is_directory(out.plot, ec) && out.plot.back() != '/', "--plot '", out.plot,
                     "' is a directory: give a file name ending in .png");
  std::string ext = std::filesystem::path(out.plot).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  check<ConfigError>(ext == ".png", "--plot '", out.plot, "' must end in .png (the plot is a PNG image)");
}


std::string pvtu_path(const std::string& vtu) {
  const auto ends = [&](const std::string& tail) {
    return vtu.size() > tail.size() && vtu.compare(vtu.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends(".pvtu")) return vtu;
  check<ConfigError>(ends(".vtu"), "--vtu '", vtu, "': under mpirun the output is a .pvtu file with one .vtu piece per "
                     "rank (give FILE.vtu or FILE.pvtu)");
  return vtu.substr(0, vtu.size() - 4) + ".pvtu";
}

void emit(const Table& table, const OutputOptions& out, const Json& extra, const std::string& plot_x,
          const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog) {
  validate_output(out);
  if (!communicator().is_root()) return;  // rank 0 speaks for all
  const TableFormat fmt = parse_table_format(out.format);
  const std::string text = format_table(fmt == TableFormat::Markdown ? displayed_columns(table, out) : table, fmt, extra);
  if (out.output.empty()) {
    std::cout << text;
    check_stream(std::cout, "the table to standard output");
  } else {
    write_file(out.output, "output file", [&](std::ostream& f) { f << text; });
  }
  if (out.plot.empty()) return;
  plot_table(table, extra, out.plot, plot_x, plot_y, plot_group, plot_title, loglog);
}

void plot_table(const Table& table, const Json& extra, const std::string& png, const std::string& plot_x,
                const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog) {
  const TemporaryFile data("vrsph-plot", ".json");
  write_file(data.path(), "temporary plot data", [&](std::ostream& f) { f << to_json(table, extra); });
  const std::string options = " --x " + plot_x + " --y " + plot_y + " --group " + plot_group + " --title " +
                              shell_quote(plot_title) + (loglog ? "" : " --linear");
  run_python(find_plot_script(), data.path(), png, options);
}

TemporaryFile::TemporaryFile(const std::string& stem, const std::string& extension)
    : path_((std::filesystem::temp_directory_path() / (stem + "-" + std::to_string(::getpid()) + extension)).string()) {}

TemporaryFile::~TemporaryFile() {
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}
}  // namespace vrsph::cli
