// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// O(N^2) reference neighbour search. Used by tests and `vrsph cloud --check` to
// verify the fast backends; same semantics as find_neighbours (strict r < radius_i).
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

NeighbourList find_neighbours_brute_force(const PointCloud& cloud, const SearchParams& params);

}  // namespace vrsph
