// SPDX-License-Identifier: BSD-3-Clause
// Closed surfaces (STL/OFF) as 3D domains: reading and validation, the fill (boundary
// particles on the surface with outward normals, interior particles inside and off it), and
// the covering radius of a general domain against the exact one of a box.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
std::string write(const std::string& name, const std::string& text) {
  const auto path = (std::filesystem::temp_directory_path() / ("vrsph_surface_" + name)).string();
  std::ofstream(path) << text;
  return path;
}

// The box [0,a]x[0,b]x[0,c] as OFF, faces outward (flip: all inward), optionally without its top.
std::string box_off(Real a, Real b, Real c, bool flip = false, bool open_top = false) {
  std::ostringstream s;  // (string appends here drew a GCC 12 -Wstringop-overflow false positive)
  s << "OFF\n8 " << (open_top ? 5 : 6) << " 0\n";
  for (int k = 0; k < 8; ++k)
    s << std::to_string((k & 1) * a) << " " << std::to_string(((k >> 1) & 1) * b) << " " << std::to_string(((k >> 2) & 1) * c) << "\n";
  const int faces[6][4] = {{0, 2, 3, 1}, {0, 1, 5, 4}, {0, 4, 6, 2}, {1, 3, 7, 5}, {2, 6, 7, 3}, {4, 5, 7, 6}};
  for (int f = 0; f < (open_top ? 5 : 6); ++f) {
    s << "4";
    for (int k = 0; k < 4; ++k) s << " " << faces[f][flip ? 3 - k : k];
    s << "\n";
  }
  return s.str();
}
}  // namespace

TEST(Surface, ReadsABoxAndFillsItWithOutwardNormals) {
  for (bool flip : {false, true}) {  // an inward-oriented file is reversed
    const ClosedSurface s = read_closed_surface(write(flip ? "flip.off" : "box.off", box_off(2, 1, 1, flip)));
    EXPECT_EQ(s.triangles(), 12u);
    EXPECT_NEAR(s.volume(), 2.0, 1e-12);
    EXPECT_NEAR(s.area(), 10.0, 1e-12);
    EXPECT_TRUE(s.contains(Vec3(1.5, 0.5, 0.5)));
    EXPECT_FALSE(s.contains(Vec3(2.5, 0.5, 0.5)));
    EXPECT_NEAR(s.distance(Vec3(1.5, 0.5, 0.4)), 0.4, 1e-12);
    for (FillPattern pattern : {FillPattern::Lattice, FillPattern::BlueNoise}) {
      GeometryFill f;
      f.spacing = 0.1;
      f.pattern = pattern;
      const PointCloud c = fill_surface(s, f);
      EXPECT_EQ(c.dim, 3);
      // About one boundary particle per spacing^2 of surface and one interior per spacing^3.
      EXPECT_NEAR(static_cast<Real>(c.count(Tag::Dirichlet)) / (10 / 0.01), 1.0, 0.1);
      const Real inner = 1.9 * 0.9 * 0.9 / 1e-3;  // the box shrunk by half a spacing
      EXPECT_NEAR(static_cast<Real>(c.count(Tag::Interior)) / inner, 1.0, 0.15) << c.count(Tag::Interior);
      for (Index i = 0; i < c.size(); ++i) {
        const auto si = static_cast<std::size_t>(i);
        const Vec3& x = c.positions[si];
        if (c.tags[si] == Tag::Interior) {
          ASSERT_TRUE(s.contains(x));
          ASSERT_GE(s.distance(x), 0.05 - 1e-12);
          continue;
        }
        ASSERT_LT(s.distance(x), 1e-12);
        const Vec3& n = c.normals[si];
        ASSERT_NEAR(n.norm(), 1.0, 1e-12);
        EXPECT_FALSE(s.contains(x + 0.01 * n)) << x.transpose() << " n " << n.transpose();
        EXPECT_TRUE(s.contains(x - 0.01 * n)) << x.transpose() << " n " << n.transpose();
      }
      // Every sharp corner of the box carries a particle, with the mean of its faces' normals.
      Index corners = 0;
      for (Index i = 0; i < c.size(); ++i) {
        const Vec3& x = c.positions[static_cast<std::size_t>(i)];
        if ((x - x.cwiseMax(Vec3::Zero()).cwiseMin(Vec3(2, 1, 1))).norm() == 0 &&
            (x[0] == 0 || x[0] == 2) && (x[1] == 0 || x[1] == 1) && (x[2] == 0 || x[2] == 1)) {
          ++corners;
          EXPECT_NEAR(std::abs(c.normals[static_cast<std::size_t>(i)][0]), 1 / std::sqrt(3.0), 1e-12);
        }
      }
      EXPECT_EQ(corners, 8);
    }
  }
}

TEST(Surface, NeumannRegionsOfAnObjTagTheirParticlesAndDirichletWinsOnTheirEdges) {
  // The unit cube, its top face (z = 1) the group "top_neumann", the rest "walls".
  std::string obj;
  for (int k = 0; k < 8; ++k) obj += "v " + std::to_string(k & 1) + " " + std::to_string((k >> 1) & 1) + " " + std::to_string((k >> 2) & 1) + "\n";
  obj += "g walls\nf 1 3 4 2\nf 1 2 6 5\nf 1 5 7 3\nf 2 4 8 6\nf 3 7 8 4\ng top_neumann\nf 5 6 8 7\n";
  const ClosedSurface s = read_closed_surface(write("regions.obj", obj));
  EXPECT_EQ(s.regions(), (std::vector<std::string>{"walls", "top_neumann"}));
  GeometryFill f;
  f.spacing = 0.1;
  const PointCloud c = fill_surface(s, f);
  Index neumann = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    if (c.tags[si] == Tag::Interior) continue;
    const bool top_inside = std::abs(x[2] - 1) < 1e-12 && x[0] > 1e-9 && x[0] < 1 - 1e-9 && x[1] > 1e-9 && x[1] < 1 - 1e-9;
    EXPECT_EQ(c.tags[si], top_inside ? Tag::Neumann : Tag::Dirichlet) << x.transpose();
    neumann += c.tags[si] == Tag::Neumann;
  }
  EXPECT_NEAR(static_cast<Real>(neumann), 81, 15);  // about (1/0.1 - 1)^2 inside the top face
}

TEST(Surface, BadSurfacesAreNamed) {
  EXPECT_THROW_MSG(read_closed_surface("/nonexistent/solid.stl"), IoError, "cannot open geometry file");
  EXPECT_THROW_MSG(read_closed_surface(write("junk.stl", "solid x\n facet normal banana\n")), InputError,
                   "junk.stl: no faces");
  EXPECT_THROW_MSG(read_closed_surface(write("empty.off", "")), InputError, "empty.off: not an OFF file");
  EXPECT_THROW_MSG(read_closed_surface(write("shape.ply", "ply\n")), ConfigError, "unknown surface format '.ply'");
  EXPECT_THROW_MSG(read_closed_surface(write("open.off", box_off(1, 1, 1, false, true))), InputError,
                   "not closed (4 border edges)");
  // Two boxes that overlap: closed, but self-intersecting.
  std::string two = box_off(1, 1, 1);
  {
    const ClosedSurface one = read_closed_surface(write("one.off", two));
    EXPECT_NEAR(one.volume(), 1, 1e-12);
  }
  std::string both = "OFF\n16 12 0\n";
  for (int b = 0; b < 2; ++b)
    for (int k = 0; k < 8; ++k)
      both += std::to_string((k & 1) + 0.5 * b) + " " + std::to_string((k >> 1) & 1) + " " + std::to_string((k >> 2) & 1) + "\n";
  const int faces[6][4] = {{0, 2, 3, 1}, {0, 1, 5, 4}, {0, 4, 6, 2}, {1, 3, 7, 5}, {2, 6, 7, 3}, {4, 5, 7, 6}};
  for (int b = 0; b < 2; ++b)
    for (const auto& f : faces) both += "4 " + std::to_string(f[0] + 8 * b) + " " + std::to_string(f[1] + 8 * b) + " " +
                                        std::to_string(f[2] + 8 * b) + " " + std::to_string(f[3] + 8 * b) + "\n";
  EXPECT_THROW_MSG(read_closed_surface(write("overlap.off", both)), InputError, "intersects itself");
  std::string huge_box = box_off(1, 1, 1);
  huge_box.replace(huge_box.find("1.000000 0.000000 0.000000"), 8, "1e200   ");
  EXPECT_THROW_MSG(read_closed_surface(write("huge.off", huge_box)), InputError, "huge.off: vertex 1 is beyond +-1e+150");
  // A binary STL tetrahedron reads; with a NaN coordinate it is refused, by name.
  const auto tetra_stl = [](float z) {
    std::string stl(80, ' ');
    const auto put = [&stl](auto v) { stl.append(reinterpret_cast<const char*>(&v), sizeof v); };
    const float P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, z}};
    const int T[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    put(std::uint32_t{4});
    for (const auto& t : T) {
      for (int k = 0; k < 3; ++k) put(0.0f);
      for (int v : t)
        for (int k = 0; k < 3; ++k) put(P[v][k]);
      put(std::uint16_t{0});
    }
    return stl;
  };
  EXPECT_NEAR(read_closed_surface(write("tetra.stl", tetra_stl(1))).volume(), 1.0 / 6, 1e-7);
  EXPECT_THROW_MSG(read_closed_surface(write("nan.stl", tetra_stl(std::nanf("")))), InputError,
                   "nan.stl: binary STL facet 1 has a coordinate that is not finite");
  const ClosedSurface s = read_closed_surface(write("box2.off", box_off(1, 1, 0.2)));
  GeometryFill f;
  f.spacing = 0.1;  // 0.2 thin: 2 particles across
  EXPECT_THROW_MSG(fill_surface(s, f), ConfigError, "too large for the geometry");
  f.spacing = 0;
  EXPECT_THROW_MSG(fill_surface(s, f), ConfigError, "spacing must be positive");
}

TEST(Surface, GeneralCoveringRadiusBracketsTheExactOneOfABox) {
  // The same perturbed lattice seen as a box cloud (exact r_N) and through a membership test
  // and a boundary sample: the general bound must contain the exact value.
  for (int dim : {2, 3}) {
    PointCloud c = vertex_lattice(Domain::unit_box(dim), dim == 2 ? 16 : 6);
    PerturbOptions po;
    po.delta = 0.4;
    po.boundary_tangential = true;
    perturb(c, po);
    const CoveringRadius exact = covering_radius(c);
    const auto inside = [dim](const Vec3& x) {
      for (int k = 0; k < dim; ++k)
        if (x[k] < 0 || x[k] > 1) return false;
      return true;
    };
    std::vector<Vec3> sample;
    const Real step = 1.0 / 64;
    if (dim == 2) {
      Polygon square;
      square.rings = {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}};
      sample = sample_polygon_boundary(square, step);
    } else {
      const ClosedSurface cube = read_closed_surface(write("cube.off", box_off(1, 1, 1)));
      sample = cube.sample(step);
    }
    const CoveringRadius general = covering_radius(c, inside, sample, step);
    EXPECT_EQ(general.uncertainty, step);
    EXPECT_LE(general.radius, exact.radius + 1e-12) << "dim " << dim;
    EXPECT_GE(general.radius + general.uncertainty, exact.radius) << "dim " << dim;
  }
}

namespace {
// Parts made alone, concatenated in order, are the whole fill.
void expect_parts_are_the_whole(const std::function<PointCloud(const GeometryFill&)>& fill, GeometryFill f) {
  const PointCloud whole = fill(f);
  for (int parts : {2, 3, 7}) {
    std::vector<Vec3> x;
    std::vector<Tag> t;
    for (int p = 0; p < parts; ++p) {
      f.part = p;
      f.parts = parts;
      const PointCloud c = fill(f);
      if (p > 0) {
        EXPECT_EQ(c.count(Tag::Dirichlet) + c.count(Tag::Neumann), 0) << "part " << p << " of " << parts;
      }
      x.insert(x.end(), c.positions.begin(), c.positions.end());
      t.insert(t.end(), c.tags.begin(), c.tags.end());
    }
    EXPECT_EQ(x, whole.positions) << parts << " parts";
    EXPECT_EQ(t, whole.tags);
  }
  f.pattern = FillPattern::BlueNoise;
  EXPECT_THROW_MSG(fill(f), ConfigError, "cannot be made in parts");
}
}  // namespace

TEST(Surface, LatticeFillsInPartsAreTheWholeFill) {
  const ClosedSurface s = read_closed_surface(write("parts.off", box_off(1, 0.6, 0.7)));
  GeometryFill f;
  f.spacing = 0.1;
  f.delta = 0.3;
  expect_parts_are_the_whole([&](const GeometryFill& g) { return fill_surface(s, g); }, f);
  const Polygon plate = parse_geojson_polygon(R"({"type": "Polygon", "coordinates": [[[0,0],[2,0],[2,1],[0,1],[0,0]],
    [[0.7,0.3],[0.7,0.7],[1.1,0.7],[1.1,0.3],[0.7,0.3]]]})", "plate.geojson");
  expect_parts_are_the_whole([&](const GeometryFill& g) { return fill_polygon(plate, g); }, f);
}
