// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The spacing and neighbour lists of a Python Cloud, computed once and reused by stencil()
// and solve() (issue 30: every call re-estimated the spacing, 0.12 s at 1e5 particles, and
// searched the neighbours again). Kept on the Python object with a fingerprint of what they
// depend on (dimension, positions, tags, normals): a cloud changed behind the cache's back is
// an InputError, never a stale answer.
#include <cstdint>
#include <map>
#include <memory>
#include <vrsph/neighbours/neighbour_list.hpp>
#include "bindings.hpp"

namespace vrsph::python {

struct CloudCache {
  std::uint64_t fingerprint = 0;
  Real spacing = -1;  ///< < 0: not computed yet
  /// By support radius, the two most recent (a third radius evicts the older).
  std::map<Real, std::shared_ptr<const NeighbourList>> neighbours;
  std::vector<Real> recent;
};

/// `self` as the library's cloud; ConfigError when it is not a vrsph.Cloud.
const PointCloud& as_cloud(const py::object& self);
/// The cache of `self` (a vrsph.Cloud), made on first use; throws InputError when the cloud
/// changed since the cache was filled. Call with the GIL held.
CloudCache& cloud_cache(const py::object& self);
/// The spacing (estimate_spacing), computed once per cloud.
Real cached_spacing(const py::object& self);
/// The neighbour list at this support radius (every non-ghost particle a row), computed once.
std::shared_ptr<const NeighbourList> cached_neighbours(const py::object& self, Real radius);

}  // namespace vrsph::python
