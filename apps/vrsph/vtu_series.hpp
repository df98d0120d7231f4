// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A VTU time series for ParaView: PREFIX_0000.vtu, PREFIX_0001.vtu, ... and PREFIX.pvd listing
// them with their times. Each file takes the cloud as it is at that time (particles that move).
#include <string>
#include <utility>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/io/vtu.hpp>

namespace vrsph::cli {

class VtuSeries {
 public:
  explicit VtuSeries(std::string prefix) : prefix_(std::move(prefix)) {}
  /// One more file; the collection is rewritten after it.
  void write(Real t, const PointCloud& cloud, const std::vector<PointField>& fields);
  std::size_t files() const { return files_.size(); }

 private:
  void write_collection() const;
  std::string prefix_;
  std::vector<std::pair<Real, std::string>> files_;
};

}  // namespace vrsph::cli
