// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: the GeoJSON polygon reader and the polygon fill (the geometry checks,
// point-in-polygon, boundary normals) at a spacing of 1/8 of the polygon's extent. Only
// vrsph::Error may escape; anything else (a crash, a sanitizer report, another exception, a
// hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/core/error.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const vrsph::Polygon p =
        vrsph::parse_geojson_polygon(std::string(reinterpret_cast<const char*>(data), size), "fuzz.geojson");
    vrsph::Vec3 lo = p.rings[0][0], hi = lo;
    for (const auto& x : p.rings[0]) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    vrsph::PolygonFill fill;
    fill.spacing = (hi - lo).maxCoeff() / 8;
    fill.delta = 0.3;
    (void)vrsph::fill_polygon(p, fill);
  } catch (const vrsph::Error&) {
  }
  return 0;
}
