// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `vrsph flow --history FILE`: every step of every run as one table row — the solver's per-step
// diagnostics (FlowStepReport: energy, max |D u|, CFL and viscous numbers, PPE iterations, the
// particles' spacing and support isotropy, shifting, wall reflections, surface particles, costs)
// and, where the case has an exact solution, its errors after that step. A CSV history is
// written as the runs go, a line per step and flushed (`tail -f` it; a run killed or blown up
// keeps its steps: this file alone is not written to a temporary one first), JSON and Markdown
// at the end, also when a run failed.
#include <fstream>
#include <string>
#include <utility>
#include <vector>
#include <vrsph/flow/flow_solver.hpp>
#include <vrsph/io/table.hpp>

namespace vrsph::cli {

class FlowHistory {
 public:
  /// path: empty (no history), or a file ending in .csv, .json or .md (ConfigError otherwise,
  /// and for a directory).
  explicit FlowHistory(std::string path);
  bool on() const { return !path_.empty(); }
  /// The step the solver just took (its last() report) of the run named by case, method and nx;
  /// `extra`: the case's own columns (errors, the cavity's steady residual).
  void record(const std::string& flow_case, const std::string& method, int nx, const FlowSolver& solver,
              const std::vector<std::pair<std::string, TableCell>>& extra = {});
  /// JSON and Markdown: writes the rows recorded so far (rank 0; nothing without a path). CSV:
  /// nothing left to write.
  void write() const;

 private:
  std::string path_;
  TableFormat format_ = TableFormat::Csv;
  Table table_;          // the columns; the rows too unless streamed
  std::ofstream stream_; // CSV on rank 0: the file as it grows
};

}  // namespace vrsph::cli
