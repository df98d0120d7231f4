// SPDX-License-Identifier: BSD-3-Clause
// A build without nlohmann-json (VRSPH_WITH_JSON=OFF): GeoJSON geometry files are refused with
// FeatureUnavailable. Writing JSON needs no part (vrsph/io/json.hpp).
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/core/features.hpp>

namespace vrsph {

Polygon parse_geojson_polygon(const std::string&, const std::string& name) {
  require_part("JSON", "the geometry file '" + name + "' (GeoJSON)");
  throw FeatureUnavailable(name);  // not reached: the part is not built
}

}  // namespace vrsph
