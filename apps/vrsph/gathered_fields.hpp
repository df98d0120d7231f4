// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The whole cloud and its point fields gathered from every rank's part, for one .vtu file or
// one plot of a distributed run (a run that --ranks auto put on ranks writes what one process
// would have written).
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph::cli {

struct WholeFields {
  PointCloud cloud;
  std::vector<PointField> fields;
};

/// On every rank: the parts concatenated in rank order (the global numbering of the
/// distributed pipeline, that of the serial cloud), positions, tags, normals (where any rank
/// has them) and each field with its columns. Serial: copies of `part` and `fields`.
/// Collective: every rank calls it with the same field names and column counts.
WholeFields gather_whole(const Communicator& comm, const PointCloud& part, const std::vector<PointField>& fields);

}  // namespace vrsph::cli
