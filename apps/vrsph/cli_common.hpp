// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Helpers shared by the vrsph subcommands: output, plotting, progress, list parsing.
#include <chrono>
#include <memory>
#include <string>
#include <vector>
#include <map>
#include <CLI/CLI.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/methods/method.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph::cli {

/// The ranks this vrsph process runs on: MPI_COMM_WORLD under mpirun with more than one
/// rank, else serial (set once by main). Only rank 0 writes tables, files and warnings.
const Communicator& communicator();
void set_communicator(const Communicator& comm);
/// Notes "vrsph: note: ..." for every method whose options resolve by the use (VRSPH's point
/// rows for operator values): an operator-level run says which rows it took, never silently.
/// The notes are printed by print_notes() after the command succeeded (an error comes first).
void note_row_forms(const std::vector<std::string>& methods, const std::map<std::string, MethodOptions>& options,
                    StencilUse use);
void print_notes();
/// --verbose (a global option): warnings come with their full lists (e.g. every infeasible row).
bool verbose();
void set_verbose(bool on);
/// The .pvtu a distributed run writes for --vtu FILE.vtu (FILE.pvtu, pieces FILE_<rank>.vtu
/// beside it); FILE.pvtu is kept. ConfigError for any other name.
std::string pvtu_path(const std::string& vtu);

/// Options every table-producing command has.
struct OutputOptions {
  std::string format = "md";
  std::string output;  ///< file, empty = stdout
  std::string plot;    ///< PNG file, empty = no plot
  /// Markdown columns: "key" (key_columns, when the command names them), "all", or a
  /// comma-separated list. CSV and JSON always carry every column.
  std::string columns = "key";
  std::vector<std::string> key_columns;
};

/// Refuses the options of `group` that were given when they do not apply: "--x applies to
/// <applies_to> only" (ConfigError), naming the first.
void reject_group_options(const CLI::App& cmd, const std::string& group, const std::string& applies_to);

/// Refuses a --columns list naming a column the table will not have (before a long run).
void validate_columns(const OutputOptions& out, const std::vector<std::string>& available);
/// Adds --columns to a command whose Markdown table shows key columns by default.
void add_columns_option(CLI::App* cmd, OutputOptions& out, std::vector<std::string> key_columns);

/// Checks the output options before a long run: a known format, --output not a
/// directory, --plot a file name ending in .png. Throws ConfigError.
void validate_output(const OutputOptions& out);

/// Writes the table in the chosen format to stdout or the output file, and the plot if asked.
/// plot_x/plot_y name the columns to plot (log-log), grouped by plot_group.
void emit(const Table& table, const OutputOptions& out, const Json& extra, const std::string& plot_x,
          const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog = true);
// A JSON text as `extra` would be one string value, not merged members: build a Json.
template <class... Rest>
void emit(const Table&, const OutputOptions&, const char*, Rest&&...) = delete;
template <class... Rest>
void emit(const Table&, const OutputOptions&, const std::string&, Rest&&...) = delete;
/// The plot part of emit alone: plot_y against plot_x per plot_group of `table` into png.
void plot_table(const Table& table, const Json& extra, const std::string& png, const std::string& plot_x,
                const std::string& plot_y, const std::string& plot_group, const std::string& plot_title, bool loglog);

template <class... Rest>
void plot_table(const Table&, const char*, Rest&&...) = delete;
template <class... Rest>
void plot_table(const Table&, const std::string&, Rest&&...) = delete;

/// "8,16,32" -> {8,16,32}; throws ConfigError naming the option on bad input.
std::vector<int> parse_int_list(const std::string& text, const std::string& option);
std::vector<std::string> parse_name_list(const std::string& text, const std::string& option);
/// Comma-separated finite numbers; ConfigError naming the option and the item otherwise.
std::vector<double> parse_real_list(const std::string& text, const std::string& option);
/// Comma-separated expressions; commas inside parentheses (max(x, y)) do not split.
std::vector<std::string> parse_expression_list(const std::string& text, const std::string& option);

/// --method-opt items: "key=value" applies to every method, "method:key=value" to one
/// (which must be in `methods`). Throws ConfigError on malformed items.
std::map<std::string, MethodOptions> parse_method_options(const std::vector<std::string>& items,
                                                          const std::vector<std::string>& methods);

/// An option given with an empty value (--u "", --method "") is a ConfigError naming
/// it, in this command and the subcommands it ran: an empty value is never a
/// silent "use the default".
void reject_empty_values(const CLI::App& command);

/// An output option (--output, --vtu, --plot, ...) naming the same file as an input option
/// (--input, --cloud-file, --config, ...) of the same command is a ConfigError: the write
/// would destroy the input.
void reject_output_over_input(const CLI::App& command);

/// --h-knn only means something with --h-mode knn: given with another mode it would be
/// silently ignored, so it is a ConfigError.
void check_h_knn_applies(const CLI::Option* h_knn, const std::string& h_mode);

/// --seed: digits only. CLI11 would read "-1" into an unsigned seed as 2^64 - 1.
CLI::Validator seed_validator();
/// Options that take a boolean value: the words CLI11 reads as one. Without it any number
/// passes (1e300 read as true).
CLI::Validator boolean_validator();

/// --threads: 0 = one per core; more threads than cores are capped to the core count
/// with a warning (oversubscription only slows the run, and the OpenMP runtime fails
/// on absurd counts). Throws ConfigError for a negative count.
void set_thread_count(int threads);

/// The Python interpreter for plots and peers: Debian's (it has python3-matplotlib; a
/// python3 earlier on PATH, from pyenv or a venv, may not); VRSPH_PYTHON overrides.
std::string python_interpreter();
/// Runs share/`script` as `script DATA PNG OPTIONS` under python_interpreter() (OPTIONS is
/// already shell-quoted and starts with a space); the PNG replaces `png` only when the script
/// succeeded, and a failure is an IoError naming png and Python's last line of error output.
void run_plot_script(const std::string& script, const std::string& data, const std::string& png,
                     const std::string& options = "");
/// A file in the temporary directory named <stem>-<pid><extension>, removed when the object
/// goes out of scope (also when the plot that reads it fails).
class TemporaryFile {
 public:
  TemporaryFile(const std::string& stem, const std::string& extension);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};
/// s in single quotes for /bin/sh.
std::string shell_quote(const std::string& s);

/// Peak resident memory of this process (VmHWM), in MiB; 0 if unknown.
double peak_memory_mib();

/// A one-line progress bar on stderr, shown only when stderr is a terminal and the
/// run has lasted more than a second.
class Progress {
 public:
  Progress();
  ~Progress();
  void update(const std::string& label, double fraction);

 private:
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_;
};

/// For a long step that reports no progress of its own (a dense eigensolver): while it
/// lives, a thread moves `progress` from `from` towards `to` as the elapsed time
/// approaches the step's up-front estimate (never past 99 % of the span).
class EstimatedProgress {
 public:
  EstimatedProgress(Progress& progress, std::string label, double from, double to, double estimated_seconds);
  ~EstimatedProgress();
  EstimatedProgress(const EstimatedProgress&) = delete;
  EstimatedProgress& operator=(const EstimatedProgress&) = delete;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace vrsph::cli
