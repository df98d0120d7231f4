// SPDX-License-Identifier: BSD-3-Clause
#include "flow_history.hpp"
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include "../cli_common.hpp"

namespace vrsph::cli {

FlowHistory::FlowHistory(std::string path) : path_(std::move(path)) {
  if (path_.empty()) return;
  std::error_code ec;
  check<ConfigError>(!std::filesystem::is_directory(path_, ec) && path_.back() != '/', "--history '", path_,
                     "' is a directory: give a file name ending in .csv, .json or .md");
  std::string ext = std::filesystem::path(path_).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  check<ConfigError>(ext == ".csv" || ext == ".json" || ext == ".md", "--history '", path_,
                     "' must end in .csv, .json or .md (the table's format)");
  format_ = parse_table_format(ext.substr(1));
  const std::filesystem::path dir = std::filesystem::path(path_).parent_path();
  check<ConfigError>(dir.empty() || std::filesystem::is_directory(dir, ec), "--history '", path_, "': the directory '",
                     dir.string(), "' does not exist");
  table_.columns = {"case", "method", "nx", "step", "t", "dt", "kinetic_energy", "max_speed", "max_div_u", "cfl",
                    "advective_number", "viscous_number", "force_number", "ppe_iterations", "ppe_setups", "viscous_iterations",
                    "min_spacing", "max_spacing", "min_support_isotropy", "max_support_growth", "max_shift", "wall_pushes",
                    "surface_particles", "error_u_mean", "error_u_inf", "error_p_mean", "decay_rate_error",
                    "steady_residual", "seconds_update", "seconds_ppe", "seconds_rhs", "seconds_viscous"};
}

void FlowHistory::record(const std::string& flow_case, const std::string& method, int nx, const FlowSolver& solver,
                         const std::vector<std::pair<std::string, TableCell>>& extra) {
  if (!on()) return;
  const FlowStepReport& r = solver.last();
  std::vector<std::pair<std::string, TableCell>> row = {
      {"case", flow_case}, {"method", method}, {"nx", static_cast<long long>(nx)},
      {"step", static_cast<long long>(r.step)}, {"t", r.t}, {"dt", r.dt}, {"kinetic_energy", r.kinetic_energy},
      {"max_speed", r.max_speed}, {"max_div_u", r.max_div_u}, {"cfl", r.cfl}, {"advective_number", r.advective_number},
      {"viscous_number", r.viscous_number}, {"force_number", r.force_number},
      {"ppe_iterations", static_cast<long long>(r.ppe_iterations)},
      {"ppe_setups", static_cast<long long>(r.ppe_setups)},
      {"viscous_iterations", static_cast<long long>(r.viscous_iterations)}, {"min_spacing", r.min_spacing},
      {"max_spacing", r.max_spacing}, {"min_support_isotropy", r.min_support_isotropy},
      {"max_support_growth", r.max_support_growth}, {"max_shift", r.max_shift},
      {"wall_pushes", static_cast<long long>(r.wall_pushes)},
      {"surface_particles", static_cast<long long>(r.surface_particles)}, {"seconds_update", r.seconds_update},
      {"seconds_ppe", r.seconds_ppe}, {"seconds_rhs", r.seconds_rhs}, {"seconds_viscous", r.seconds_viscous}};
  row.insert(row.end(), extra.begin(), extra.end());
  table_.add_row(row);
  if (format_ != TableFormat::Csv) return;
  if (communicator().rank() == 0) {
    if (!stream_.is_open()) {  // at the first step: a command refused before it leaves no file
      stream_.open(path_, std::ios::out | std::ios::trunc);
      if (!stream_) throw IoError(detail::concat("--history '", path_, "': cannot write the file"));
      stream_ << csv_header(table_);
    }
    stream_ << csv_row(table_.rows.back()) << std::flush;
    if (!stream_) throw IoError(detail::concat("--history '", path_, "': writing the file failed (disk full?)"));
  }
  table_.rows.clear();  // written: a long run's history is not kept twice
}

void FlowHistory::write() const {
  if (!on() || communicator().rank() != 0 || format_ == TableFormat::Csv) return;
  const std::string text = format_table(table_, format_);
  write_file(path_, "flow history", [&text](std::ostream& f) { f << text; });
}

}  // namespace vrsph::cli
