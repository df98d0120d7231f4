// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// 2D domains as polygons with holes, read from GeoJSON (RFC 7946: a Polygon geometry, or a
// Feature / FeatureCollection holding exactly one; the first ring is the outer boundary, the
// others holes; ring orientation is not relied on), and filled with particles: boundary
// particles along every edge at about the requested spacing with the domain's outward unit
// normals, interior particles on a lattice (optionally perturbed) or as blue noise, kept at
// least half a spacing from the boundary.
#include <string>
#include <vector>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct Polygon {
  std::vector<std::vector<Vec3>> rings;  ///< ring 0 outer, the rest holes; not closed (first != last)
};

/// Throws IoError (unreadable file) or InputError naming the file and the problem: not
/// GeoJSON, not one Polygon, a ring with fewer than 3 distinct vertices, non-finite or 3D
/// coordinates, edges that cross (naming the two rings and edges), a hole outside the outer ring.
Polygon read_geojson_polygon(const std::string& path);
Polygon parse_geojson_polygon(const std::string& text, const std::string& name);

using PolygonFill = GeometryFill;

/// Boundary particles tagged Dirichlet (see tag_boundary to change them), interior ones
/// Interior; domain shape None, spacing set. Throws ConfigError when the spacing is not
/// positive or too coarse for the polygon (fewer than 3 particles across its smallest ring).
PointCloud fill_polygon(const Polygon& polygon, const PolygonFill& fill);

/// True if x lies inside the polygon (inside the outer ring and outside every hole).
bool inside_polygon(const Polygon& polygon, const Vec3& x);

/// Distance from x to the polygon's boundary (its nearest edge).
Real distance_to_polygon_boundary(const Polygon& polygon, const Vec3& x);

/// Points along every edge no farther than `step` from any boundary point (vertices
/// included), e.g. to bound the covering radius.
std::vector<Vec3> sample_polygon_boundary(const Polygon& polygon, Real step);

}  // namespace vrsph
