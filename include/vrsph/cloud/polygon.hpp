// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// 2D domains as polygons with holes, read from GeoJSON (RFC 7946: a Polygon or MultiPolygon
// geometry, or a Feature / FeatureCollection holding exactly one), and filled with particles:
// boundary particles along every edge at about the requested spacing with the domain's
// outward unit normals, interior particles on a lattice (optionally perturbed) or as blue
// noise, kept at least half a spacing from the boundary. The domain is the even-odd region of
// all rings (a point is inside when an odd number of rings encloses it): a Polygon's first ring
// bounds it, its others are holes, a ring inside a hole bounds an island (filled), and the
// parts of a MultiPolygon lie apart or inside one another's holes. Ring orientation is not
// relied on.
#include <string>
#include <vector>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct Polygon {
  /// Not closed (first != last). The domain is what an odd number of rings encloses: ring 0
  /// and the rings at even nesting depth bound it from outside, those at odd depth are holes.
  std::vector<std::vector<Vec3>> rings;
};

/// Throws IoError (unreadable file) or InputError naming the file and the problem: not
/// GeoJSON, not one Polygon or MultiPolygon, a ring with fewer than 3 distinct vertices,
/// non-finite or 3D coordinates, edges that cross (naming the two rings and edges), a hole
/// outside its polygon's outer ring, a MultiPolygon part inside another part's solid region.
Polygon read_geojson_polygon(const std::string& path);
Polygon parse_geojson_polygon(const std::string& text, const std::string& name);

using PolygonFill = GeometryFill;

/// Nesting depth of every ring: how many other rings enclose it (even: the domain lies
/// inside the ring; odd: the ring bounds a hole).
std::vector<int> ring_depths(const Polygon& polygon);

/// Boundary particles tagged Dirichlet (see tag_boundary to change them), interior ones
/// Interior; domain shape None, spacing set. Throws ConfigError when the spacing is not
/// positive or too coarse for the polygon (fewer than 3 particles across its smallest ring).
PointCloud fill_polygon(const Polygon& polygon, const PolygonFill& fill);

/// True if x lies inside the domain (an odd number of rings encloses it).
bool inside_polygon(const Polygon& polygon, const Vec3& x);

/// Distance from x to the polygon's boundary (its nearest edge).
Real distance_to_polygon_boundary(const Polygon& polygon, const Vec3& x);

/// Points along every edge no farther than `step` from any boundary point (vertices
/// included), e.g. to bound the covering radius.
std::vector<Vec3> sample_polygon_boundary(const Polygon& polygon, Real step);

}  // namespace vrsph
