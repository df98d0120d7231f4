// SPDX-License-Identifier: BSD-3-Clause
// GeoJSON polygons (the optional part JSON: nlohmann-json parses what users give us).
#include <algorithm>
#include <nlohmann/json.hpp>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include "polygon_checks.hpp"

namespace vrsph {

namespace {
using json = nlohmann::json;

// The Polygon or MultiPolygon geometry inside a GeoJSON document (geometry, Feature or a
// collection of one).
const json& polygon_geometry(const json& doc, const std::string& name) {
  check<InputError>(doc.is_object() && doc.contains("type") && doc["type"].is_string(), name,
                    ": not a GeoJSON object (no \"type\")");
  const std::string type = doc["type"];
  if (type == "Polygon" || type == "MultiPolygon") return doc;
  if (type == "Feature") {
    check<InputError>(doc.contains("geometry") && doc["geometry"].is_object(), name, ": Feature without a geometry");
    return polygon_geometry(doc["geometry"], name);
  }
  if (type == "FeatureCollection") {
    check<InputError>(doc.contains("features") && doc["features"].is_array() && doc["features"].size() == 1, name,
                      ": a FeatureCollection must hold exactly one Feature (the domain; several parts: one "
                      "MultiPolygon)");
    return polygon_geometry(doc["features"][0], name);
  }
  throw InputError(detail::concat(name, ": GeoJSON type '", type, "' is not a Polygon or MultiPolygon (the domain "
                                        "must be an area)"));
}

}  // namespace

namespace {
// The deepest nesting of arrays and objects in a JSON text, strings skipped. A polygon needs
// about 7 levels; a document nested thousands deep is refused before it is parsed, so that
// no parser, destructor or walk over it can run out of stack.
std::size_t json_depth(const std::string& text) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (in_string) {
      if (c == '\\') ++k;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}
constexpr std::size_t kMaxJsonDepth = 64;
}  // namespace

Polygon parse_geojson_polygon(const std::string& text, const std::string& name) {
  const std::size_t depth = json_depth(text);
  check<InputError>(depth <= kMaxJsonDepth, name, ": JSON nested ", depth, " levels deep (a GeoJSON polygon needs fewer "
                    "than ", kMaxJsonDepth, "; not a geometry file)");
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {  // syntax errors, and numbers out of range (out_of_range.406)
    throw InputError(detail::concat(name, ": not valid JSON (", e.what(), ")"));
  }
  const json& g = polygon_geometry(doc, name);
  const bool multi = g["type"] == "MultiPolygon";
  check<InputError>(g.contains("coordinates") && g["coordinates"].is_array() && !g["coordinates"].empty(), name, ": ",
                    multi ? "MultiPolygon" : "Polygon", " without coordinates");
  Polygon p;
  std::vector<std::size_t> part_of, first_ring;
  const json& parts = g["coordinates"];
  for (std::size_t part = 0; part < (multi ? parts.size() : 1); ++part) {
    const json& rings = multi ? parts[part] : parts;
    check<InputError>(rings.is_array() && !rings.empty(), name, ": polygon ", part, " is not an array of rings");
    const std::size_t outer = p.rings.size();
    for (std::size_t r = 0; r < rings.size(); ++r) {
      const json& ring = rings[r];
      const std::size_t index = p.rings.size();  // ring number across all parts (messages and checks)
      check<InputError>(ring.is_array(), name, ": ring ", index, " is not an array of positions");
      std::vector<Vec3> pts;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const json& pos = ring[k];
        check<InputError>(pos.is_array() && pos.size() >= 2 && pos[0].is_number() && pos[1].is_number(), name, ": ring ",
                          index, " position ", k, " is not [x, y]");
        check<InputError>(pos.size() == 2 || (pos[2].is_number() && pos[2].get<double>() == 0), name, ": ring ", index,
                          " position ", k, " has a non-zero z (a 2D domain is expected)");
        const Vec3 x(pos[0].get<double>(), pos[1].get<double>(), 0);
        check<InputError>(x.allFinite() && x.cwiseAbs().maxCoeff() <= max_coordinate, name, ": ring ", index, " position ",
                          k, " is not finite or beyond +-", max_coordinate, " (rescale the geometry)");
        if (pts.empty() || x != pts.back()) pts.push_back(x);  // repeated vertices collapse
      }
      if (pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();  // GeoJSON rings are closed
      p.rings.push_back(std::move(pts));
      part_of.push_back(part);
      first_ring.push_back(outer);
    }
  }
  detail::check_polygon(p, part_of, first_ring, name);
  return p;
}

}  // namespace vrsph
