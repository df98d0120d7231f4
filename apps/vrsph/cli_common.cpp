// SPDX-License-Identifier: BSD-3-Clause
#include "cli_common.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif
#include <unistd.h>
#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/resources.hpp>
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

namespace {
Communicator& the_communicator() {
  static Communicator comm;
  return comm;
}
}  // namespace

const Communicator& communicator() { return the_communicator(); }
void set_communicator(const Communicator& comm) { the_communicator() = comm; }
namespace {
bool& verbose_flag() {
  static bool on = false;
  return on;
}
}  // namespace
bool verbose() { return verbose_flag(); }
namespace {
std::vector<std::string>& pending_notes() {
  static std::vector<std::string> notes;
  return notes;
}
}  // namespace
void note_row_forms(const std::vector<std::string>& methods, const std::map<std::string, MethodOptions>& options,
                    StencilUse use) {
  for (const auto& m : methods) {
    const std::string note = builtin_methods().create(m, options_for(options, m))->row_forms(use);
    if (!note.empty()) pending_notes().push_back(note);
  }
}
void print_notes() {
  for (const auto& n : pending_notes()) std::cerr << "vrsph: note: " << n << '\n';
  pending_notes().clear();
}
void set_verbose(bool on) { verbose_flag() = on; }

std::string pvtu_path(const std::string& vtu) {
  const auto ends = [&](const std::string& tail) {
    return vtu.size() > tail.size() && vtu.compare(vtu.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends(".pvtu")) return vtu;
  check<ConfigError>(ends(".vtu"), "--vtu '", vtu, "': under mpirun the output is a .pvtu file with one .vtu piece per "
                     "rank (give FILE.vtu or FILE.pvtu)");
  return vtu.substr(0, vtu.size() - 4) + ".pvtu";
}

void emit(const Table& table, const OutputOptions& out, const std::string& extra_json, const std::string& plot_x,
          const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog) {
  validate_output(out);
  if (!communicator().is_root()) return;  // rank 0 speaks for all
  const TableFormat fmt = parse_table_format(out.format);
  const std::string text = format_table(fmt == TableFormat::Markdown ? displayed_columns(table, out) : table, fmt, extra_json);
  if (out.output.empty()) {
    std::cout << text;
    check_stream(std::cout, "the table to standard output");
  } else {
    write_file(out.output, "output file", [&](std::ostream& f) { f << text; });
  }
  if (out.plot.empty()) return;
  plot_table(table, extra_json, out.plot, plot_x, plot_y, plot_group, plot_title, loglog);
}

void plot_table(const Table& table, const std::string& extra_json, const std::string& png, const std::string& plot_x,
                const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog) {
  const TemporaryFile data("vrsph-plot", ".json");
  write_file(data.path(), "temporary plot data", [&](std::ostream& f) { f << to_json(table, extra_json); });
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

void set_thread_count(int threads) {
  check<ConfigError>(threads >= 0, "--threads must be >= 0 (0 = one per core), got ", threads);
#ifdef _OPENMP
  const int cores = omp_get_num_procs();
  if (threads > cores)
    std::cerr << "vrsph: warning: --threads " << threads << " is more than the " << cores
              << " cores of this machine; using " << cores << '\n';
  omp_set_num_threads(threads == 0 || threads > cores ? cores : threads);
#else
  if (threads > 1)
    std::cerr << "vrsph: warning: --threads " << threads << " is more than the 1 thread of this build (no OpenMP); using 1\n";
#endif
}

double peak_memory_mib() { return static_cast<double>(peak_resident_memory_bytes()) / (1024.0 * 1024.0); }

Progress::Progress() : enabled_(::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (shown_) std::cerr << "\r\033[K" << std::flush;
}

void Progress::update(const std::string& label, double fraction) {
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed < 1.0 && !shown_) return;
  shown_ = true;
  const int width = 30, filled = static_cast<int>(fraction * width + 0.5);
  std::cerr << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << static_cast<int>(100 * fraction)
            << "% " << label << " (" << static_cast<int>(elapsed) << " s)\033[K" << std::flush;
}

struct EstimatedProgress::State {
  std::mutex mutex;
  std::condition_variable stop_cv;
  bool stop = false;
  std::thread thread;
};

EstimatedProgress::EstimatedProgress(Progress& progress, std::string label, double from, double to,
                                     double estimated_seconds)
    : state_(std::make_unique<State>()) {
  const auto start = std::chrono::steady_clock::now();
  state_->thread = std::thread([this, &progress, label = std::move(label), from, to, estimated_seconds, start] {
    std::unique_lock lock(state_->mutex);
    while (!state_->stop_cv.wait_for(lock, std::chrono::milliseconds(250), [this] { return state_->stop; })) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress.update(label, from + (to - from) * std::min(0.99, t / std::max(estimated_seconds, 1e-3)));
    }
  });
}

EstimatedProgress::~EstimatedProgress() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->stop_cv.notify_all();
  state_->thread.join();
}

}  // namespace vrsph::cli
