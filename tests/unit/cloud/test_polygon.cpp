// SPDX-License-Identifier: BSD-3-Clause
// Polygon domains from GeoJSON: parsing, validation of the geometry, and the fill (boundary
// particles with the domain's outward normals, interior particles off the boundary).
#include <cmath>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// A 2 x 1 plate with a square hole, as a Feature; the hole given clockwise, the outer ring
// counter-clockwise (RFC 7946) — the reader must not rely on either.
const char* plate = R"({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [
  [[0,0],[2,0],[2,1],[0,1],[0,0]],
  [[0.7,0.3],[0.7,0.7],[1.1,0.7],[1.1,0.3],[0.7,0.3]]]}})";
}  // namespace

TEST(Polygon, FillsWithOutwardNormalsAndKeepsInteriorOffTheBoundary) {
  VRSPH_REQUIRE_PART("JSON");  // GeoJSON (Features checks the refusal without it)
  const Polygon p = parse_geojson_polygon(plate, "plate.geojson");
  ASSERT_EQ(p.rings.size(), 2u);
  EXPECT_TRUE(inside_polygon(p, Vec3(0.3, 0.5, 0)));
  EXPECT_FALSE(inside_polygon(p, Vec3(0.9, 0.5, 0)));  // in the hole
  PolygonFill f;
  f.spacing = 0.05;
  const PointCloud c = fill_polygon(p, f);
  EXPECT_EQ(c.count(Tag::Dirichlet), 2 * (40 + 20) + 4 * 8);  // outer 6 units, hole 1.6 units at 0.05
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    if (c.tags[si] == Tag::Interior) {
      EXPECT_TRUE(inside_polygon(p, x));
      continue;
    }
    const Vec3& n = c.normals[si];
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    // Outward: a step along n leaves the domain (into the hole on the hole's edges).
    EXPECT_FALSE(inside_polygon(p, x + 0.01 * n)) << x.transpose() << " n " << n.transpose();
    EXPECT_TRUE(inside_polygon(p, x - 0.01 * n)) << x.transpose() << " n " << n.transpose();
  }
  f.delta = 0.3;
  const PointCloud perturbed = fill_polygon(p, f);
  EXPECT_EQ(perturbed.count(Tag::Dirichlet), c.count(Tag::Dirichlet));
}

TEST(Polygon, BadGeometriesAreNamed) {
  VRSPH_REQUIRE_PART("JSON");  // GeoJSON (Features checks the refusal without it)
  EXPECT_THROW_MSG(parse_geojson_polygon("{", "g.json"), InputError, "g.json: not valid JSON");
  // A number beyond double's range (found by the geojson fuzzer: nlohmann's out_of_range).
  EXPECT_THROW_MSG(parse_geojson_polygon("11e41441", "g.json"), InputError, "g.json: not valid JSON");
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "MultiPolygon", "coordinates": []})", "g.json"), InputError,
                   "MultiPolygon without coordinates");
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "LineString", "coordinates": [[0,0],[1,1]]})", "g.json"), InputError,
                   "GeoJSON type 'LineString' is not a Polygon or MultiPolygon");
  // A part inside another part's area (not in a hole): the union is meant, even-odd would cut it out.
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "MultiPolygon", "coordinates": [[[[0,0],[4,0],[4,4],[0,4]]],
                                             [[[1,1],[2,1],[2,2],[1,2]]]]})", "g.json"),
                   InputError, "polygon 1 of the MultiPolygon lies inside another polygon's area");
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "Polygon", "coordinates": [[[0,0],[1,0],[0,0]]]})", "g.json"),
                   InputError, "ring 0 has 2 distinct vertices");
  // A bow tie: edges 0 and 2 cross.
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "Polygon", "coordinates": [[[0,0],[2,1],[2,0],[0,2],[0,0]]]})", "g.json"),
                   InputError, "edges cross or touch: ring 0 edge 0 and ring 0 edge 2");
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1],[0,1]],
                                             [[2,2],[3,2],[3,3]]]})", "g.json"),
                   InputError, "hole 1 of polygon 0 lies outside its outer ring");
  EXPECT_THROW_MSG(parse_geojson_polygon(R"({"type": "Polygon", "coordinates": [[[0,0,1],[1,0,1],[1,1,1]]]})", "g.json"),
                   InputError, "non-zero z");
  const Polygon p = parse_geojson_polygon(plate, "plate.geojson");
  PolygonFill f;
  f.spacing = 0.2;  // the hole spans 0.4: fewer than 3 particles across
  EXPECT_THROW_MSG(fill_polygon(p, f), ConfigError, "too large for the geometry");
  f.spacing = -1;
  EXPECT_THROW_MSG(fill_polygon(p, f), ConfigError, "spacing must be positive");
  EXPECT_THROW_MSG(read_geojson_polygon("/nonexistent/shape.geojson"), IoError, "cannot open geometry file");
}

namespace {
// Every boundary particle's normal points out of the domain, every interior particle is inside.
void expect_outward_normals(const Polygon& p, const PointCloud& c) {
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    if (c.tags[si] == Tag::Interior) {
      EXPECT_TRUE(inside_polygon(p, x)) << x.transpose();
      continue;
    }
    const Vec3& n = c.normals[si];
    EXPECT_FALSE(inside_polygon(p, x + 0.01 * n)) << x.transpose() << " n " << n.transpose();
    EXPECT_TRUE(inside_polygon(p, x - 0.01 * n)) << x.transpose() << " n " << n.transpose();
  }
}
std::size_t interior_within(const PointCloud& c, const Vec3& lo, const Vec3& hi) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < c.positions.size(); ++i)
    k += c.tags[i] == Tag::Interior && (c.positions[i].head<2>().array() > lo.head<2>().array()).all() &&
         (c.positions[i].head<2>().array() < hi.head<2>().array()).all();
  return k;
}
}  // namespace

// A ring inside a hole bounds an island: filled, with normals out of the island (issue 31:
// it used to be left empty with its ring particles floating in the void, then refused).
TEST(Polygon, AnIslandInAHoleIsFilled) {
  VRSPH_REQUIRE_PART("JSON");  // GeoJSON (Features checks the refusal without it)
  const char* nested = R"({"type": "Polygon", "coordinates": [
    [[0,0],[3,0],[3,3],[0,3]], [[0.5,0.5],[2.5,0.5],[2.5,2.5],[0.5,2.5]], [[1,1],[2,1],[2,2],[1,2]]]})";
  const Polygon p = parse_geojson_polygon(nested, "island.geojson");
  EXPECT_EQ(ring_depths(p), (std::vector<int>{0, 1, 2}));
  EXPECT_TRUE(inside_polygon(p, Vec3(0.25, 1.5, 0)));   // the frame
  EXPECT_FALSE(inside_polygon(p, Vec3(0.75, 1.5, 0)));  // the moat
  EXPECT_TRUE(inside_polygon(p, Vec3(1.5, 1.5, 0)));    // the island
  PolygonFill f;
  f.spacing = 0.1;
  const PointCloud c = fill_polygon(p, f);
  expect_outward_normals(p, c);
  // The island's 1 x 1 square holds its lattice: 9 x 9 interior points at least 0.05 from its edges.
  EXPECT_EQ(interior_within(c, Vec3(1, 1, 0), Vec3(2, 2, 0)), 81u);
  EXPECT_EQ(interior_within(c, Vec3(0.55, 0.55, 0), Vec3(0.95, 2.45, 0)), 0u);  // nothing in the moat
}

// A MultiPolygon: two parts side by side, and one inside the other's hole; the same domain as
// the nested Polygon above.
TEST(Polygon, MultiPolygonPartsApartOrInHoles) {
  VRSPH_REQUIRE_PART("JSON");  // GeoJSON (Features checks the refusal without it)
  const char* two = R"({"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [
    [[[0,0],[1,0],[1,1],[0,1]]], [[[2,0],[3,0],[3,1],[2,1]]]]}})";
  const Polygon p = parse_geojson_polygon(two, "two.geojson");
  EXPECT_TRUE(inside_polygon(p, Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(inside_polygon(p, Vec3(2.5, 0.5, 0)));
  EXPECT_FALSE(inside_polygon(p, Vec3(1.5, 0.5, 0)));
  PolygonFill f;
  f.spacing = 0.1;
  const PointCloud c = fill_polygon(p, f);
  expect_outward_normals(p, c);
  EXPECT_EQ(interior_within(c, Vec3(0, 0, 0), Vec3(1, 1, 0)), interior_within(c, Vec3(2, 0, 0), Vec3(3, 1, 0)));
  EXPECT_EQ(c.count(Tag::Dirichlet), 80);
  const char* moat = R"({"type": "MultiPolygon", "coordinates": [
    [[[0,0],[3,0],[3,3],[0,3]], [[0.5,0.5],[2.5,0.5],[2.5,2.5],[0.5,2.5]]], [[[1,1],[2,1],[2,2],[1,2]]]]})";
  const Polygon q = parse_geojson_polygon(moat, "moat.geojson");
  const PointCloud d = fill_polygon(q, f);
  expect_outward_normals(q, d);
  EXPECT_EQ(interior_within(d, Vec3(1, 1, 0), Vec3(2, 2, 0)), 81u);
}
