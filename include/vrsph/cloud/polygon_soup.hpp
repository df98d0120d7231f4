// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Triangle/polygon surfaces as files hold them: STL (ASCII or binary), OFF and OBJ, read into
// a polygon soup (points and faces as index lists). Written here rather than taken from
// CGAL's readers: fuzzing found CGAL 5.5's OBJ and PLY readers reading out of bounds on
// malformed files, and our own readers name the line of a problem. CGAL then turns the
// validated soup into a mesh (surface.cpp).
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct PolygonSoup {
  std::vector<Vec3> points;
  std::vector<std::vector<std::size_t>> faces;  ///< each at least 3 indices into points
  /// Named surface regions: OBJ groups (`g name`, else `o name`) and the solids of a
  /// multi-solid ASCII STL (`solid name`). face_region[f] indexes regions; both empty when
  /// the file names none.
  std::vector<std::string> regions;
  std::vector<std::size_t> face_region;
};

/// By extension: .stl, .off, .obj (any case). Throws IoError (missing/unreadable file),
/// ConfigError (another extension) or InputError naming the file, line (or STL facet) and
/// problem: a token that is not a number, an index out of range, a face with fewer than 3
/// vertices, counts that do not match, a truncated binary STL, no faces at all.
PolygonSoup read_polygon_soup(const std::string& path);

PolygonSoup parse_stl(const std::string& bytes, const std::string& name);
PolygonSoup parse_off(const std::string& text, const std::string& name);
PolygonSoup parse_obj(const std::string& text, const std::string& name);

}  // namespace vrsph
