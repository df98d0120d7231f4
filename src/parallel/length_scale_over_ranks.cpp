// SPDX-License-Identifier: BSD-3-Clause
// length_scale of a cloud spread over ranks (distributed_cloud.hpp): the largest side of the
// bounding box of every rank's part; needs only the reductions, so every build has it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/parallel/distributed_cloud.hpp>

namespace vrsph {

Real length_scale(const PointCloud& part, const Communicator& comm) { return length_scale(part, {}, comm); }

Real length_scale(const PointCloud& part, std::span<const char> counted, const Communicator& comm) {
  Real side = 0;
  for (int k = 0; k < 3; ++k) {
    Real lo = std::numeric_limits<Real>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < part.positions.size(); ++i) {
      if (!counted.empty() && !counted[i]) continue;
      lo = std::min(lo, part.positions[i][k]);
      hi = std::max(hi, part.positions[i][k]);
    }
    side = std::max(side, max_over_ranks(comm, hi) - min_over_ranks(comm, lo));
  }
  return side > 0 && std::isfinite(side) ? side : 1;
}

}  // namespace vrsph
