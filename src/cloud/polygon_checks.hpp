// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The checks a polygon read from a file must pass (polygon.cpp), shared with the GeoJSON reader.
#include <string>
#include <vector>
#include <vrsph/cloud/polygon.hpp>

namespace vrsph::detail {

/// Throws InputError naming `name` unless every ring has 3 vertices and an area, no two edges
/// meet, holes lie in their own part's outer ring and parts lie apart. part_of[r]: the
/// MultiPolygon part ring r belongs to; first_ring[r]: that part's outer ring.
void check_polygon(const Polygon& p, const std::vector<std::size_t>& part_of, const std::vector<std::size_t>& first_ring,
                   const std::string& name);

}  // namespace vrsph::detail
