// SPDX-License-Identifier: BSD-3-Clause
// length_scale of a cloud spread over ranks (distributed_cloud.hpp): the largest side of the
// bounding box of every rank's part; needs only the reductions, so every build has it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/parallel/distributed_cloud.hpp>

namespace vrsph {

Real length_scale(const PointCloud& part, const Communicator& comm) {
  Real side = 0;
  for (int k = 0; k < 3; ++k) {
    Real lo = std::numeric_limits<Real>::infinity(), hi = -lo;
    for (const Vec3& x : part.positions) {
      lo = std::min(lo, x[k]);
      hi = std::max(hi, x[k]);
    }
    side = std::max(side, max_over_ranks(comm, hi) - min_over_ranks(comm, lo));
  }
  return side > 0 && std::isfinite(side) ? side : 1;
}

}  // namespace vrsph
