// SPDX-License-Identifier: BSD-3-Clause
// VTU time series (vtu_series.hpp).
#include <filesystem>
#include <ostream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>
#include "vtu_series.hpp"

namespace vrsph::cli {

void VtuSeries::write(Real t, const PointCloud& cloud, const std::vector<PointField>& fields) {
  const std::string number = std::to_string(files_.size());
  const std::string name =
      detail::concat(prefix_, "_", std::string(4 - std::min<std::size_t>(4, number.size()), '0'), number, ".vtu");
  write_vtu(name, cloud, fields, VtuFormat::Binary);
  files_.emplace_back(t, std::filesystem::path(name).filename().string());
  write_collection();
}

// Rewritten (atomically) after every file: at any moment, also after a kill, the PVD lists
// exactly this run's finished files, never a previous run's files of the same prefix.
void VtuSeries::write_collection() const {
  write_file(prefix_ + ".pvd", "VTU time series", [&](std::ostream& f) {
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
    for (const auto& [t, file] : files_) f << "    <DataSet timestep=\"" << t << "\" file=\"" << file << "\"/>\n";
    f << "  </Collection>\n</VTKFile>\n";
  });
}

}  // namespace vrsph::cli
