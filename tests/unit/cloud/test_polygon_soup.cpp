// SPDX-License-Identifier: BSD-3-Clause
// Surface files as polygon soups: STL (ASCII and binary), OFF and OBJ, with the line of
// every problem named; the cases fuzzing found in CGAL's readers (OBJ index 0) are errors.
#include <cstdint>
#include <string>
#include <vrsph/cloud/polygon_soup.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
const char* tetra_obj = "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1 3 2\nf 1 2 4\nf 1//1 4//1 3//1\nf -3 -2 -1\n";
}  // namespace

TEST(PolygonSoup, ReadsStlOffAndObjAlike) {
  const PolygonSoup obj = parse_obj(tetra_obj, "t.obj");
  ASSERT_EQ(obj.points.size(), 4u);
  ASSERT_EQ(obj.faces.size(), 4u);
  EXPECT_EQ(obj.faces[2], (std::vector<std::size_t>{0, 3, 2}));
  EXPECT_EQ(obj.faces[3], (std::vector<std::size_t>{1, 2, 3}));  // negative: relative to the last vertex
  const PolygonSoup off = parse_off("OFF\n# comment\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3 255 0 0\n3 0 3 2\n3 1 2 3\n", "t.off");
  EXPECT_EQ(off.points, obj.points);
  EXPECT_EQ(off.faces[1], (std::vector<std::size_t>{0, 1, 3}));  // a colour after the indices is ignored
  std::string stl = "solid t\n";
  for (const auto& f : off.faces) {
    stl += " facet normal 0 0 0\n  outer loop\n";
    for (auto v : f) stl += "   vertex " + std::to_string(off.points[v][0]) + " " + std::to_string(off.points[v][1]) + " " +
                            std::to_string(off.points[v][2]) + "\n";
    stl += "  endloop\n endfacet\n";
  }
  stl += "endsolid t\n";
  const PolygonSoup ascii = parse_stl(stl, "t.stl");
  EXPECT_EQ(ascii.points.size(), 4u);  // corners merged by coordinates
  EXPECT_EQ(ascii.faces.size(), 4u);
}

TEST(PolygonSoup, ProblemsAreNamedWithTheLine) {
  EXPECT_THROW_MSG(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "z.obj"), InputError,
                   "z.obj:4: vertex index 0 does not name one of the 3 vertices");
  EXPECT_THROW_MSG(parse_obj("v 0 0 0\nf 1 2 3\n", "f.obj"), InputError, "f.obj:2: vertex index 2");
  EXPECT_THROW_MSG(parse_obj("v 0 zero 0\n", "x.obj"), InputError, "x.obj:1: y 'zero' is not a number");
  EXPECT_THROW_MSG(parse_obj("v 0 0 0\nv 1 0 0\nf 1 2\n", "s.obj"), InputError, "s.obj:3: a face with 2 vertices");
  EXPECT_THROW_MSG(parse_obj("# nothing\n", "e.obj"), InputError, "e.obj: no faces");
  EXPECT_THROW_MSG(parse_off("OFF\n1 1 0\n0 0 0\n3 0 1 2\n", "i.off"), InputError, "i.off:4: vertex index 1 is outside 0..0");
  EXPECT_THROW_MSG(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n", "t.off"), InputError, "t.off:4: the file ends after 2 of 3 vertices");
  EXPECT_THROW_MSG(parse_off("OFF\n99999999 1 0\n", "c.off"), InputError, "more than the file can hold");
  EXPECT_THROW_MSG(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n", "n.off"), InputError,
                   "n.off:5: a vertex coordinate is not finite");
  EXPECT_THROW_MSG(parse_stl("solid s\n outer loop\n vertex 0 0\n", "v.stl"), InputError,
                   "v.stl:3: 'vertex' needs three coordinates");
  EXPECT_THROW_MSG(parse_stl("solid s\n outer loop\n vertex 0 0 0\n", "l.stl"), InputError, "the file ends inside a facet's loop");
  EXPECT_THROW_MSG(parse_stl("hello\n", "h.stl"), InputError, "neither an ASCII STL");
  std::string truncated(84, '\0');
  truncated[80] = 5;  // five facets announced, none there: not binary by size, and not ASCII
  EXPECT_THROW_MSG(parse_stl(truncated, "b.stl"), InputError, "neither an ASCII STL");
  EXPECT_THROW_MSG(read_polygon_soup("/nonexistent/x.stl"), IoError, "cannot open geometry file");
  EXPECT_THROW_MSG(read_polygon_soup("x.ply"), ConfigError, "unknown surface format '.ply'");
}

TEST(PolygonSoup, RegionsFromObjGroupsAndStlSolids) {
  const PolygonSoup obj = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\ng wall\nf 1 2 4\nf 1 4 3\ng Top Neumann\nf 2 3 4\n", "r.obj");
  EXPECT_EQ(obj.regions, (std::vector<std::string>{"", "wall", "Top Neumann"}));
  EXPECT_EQ(obj.face_region, (std::vector<std::size_t>{0, 1, 1, 2}));
  EXPECT_TRUE(parse_obj(tetra_obj, "t.obj").regions.empty());
  const std::string facet = " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n";
  const PolygonSoup one = parse_stl("solid only\n" + facet + "endsolid only\n", "one.stl");
  EXPECT_TRUE(one.regions.empty());  // one solid: no regions to tell apart
  const PolygonSoup two = parse_stl("solid a\n" + facet + facet + "endsolid a\nsolid b neumann\n" + facet + "endsolid\n", "two.stl");
  EXPECT_EQ(two.regions, (std::vector<std::string>{"a", "b neumann"}));
  EXPECT_EQ(two.face_region, (std::vector<std::size_t>{0, 0, 1}));
}

// A binary STL whose 80-byte header starts with "solid" (exporters write that) is binary: the
// size 84 + 50 per triangle decides, not the first word (issue 31, class 10).
TEST(PolygonSoup, BinaryStlWithASolidHeaderIsReadAsBinary) {
  std::string bytes = "solid tetrahedron, binary despite the first word";
  bytes.resize(80, ' ');
  const auto put32 = [&bytes](std::uint32_t v) { bytes.append(reinterpret_cast<const char*>(&v), 4); };
  const auto putf = [&bytes](float v) { bytes.append(reinterpret_cast<const char*>(&v), 4); };
  const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  put32(4);
  for (const auto& f : faces) {
    for (int k = 0; k < 3; ++k) putf(0);  // normal (ignored)
    for (const int v : f)
      for (int k = 0; k < 3; ++k) putf(p[v][k]);
    bytes.append(2, '\0');  // attribute byte count
  }
  ASSERT_EQ(bytes.size(), 84u + 4 * 50);
  const PolygonSoup soup = parse_stl(bytes, "solid_header.stl");
  EXPECT_EQ(soup.faces.size(), 4u);
  EXPECT_EQ(soup.points.size(), 4u);  // shared corners merged
}
