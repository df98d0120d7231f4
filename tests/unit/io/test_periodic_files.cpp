// SPDX-License-Identifier: BSD-3-Clause
// Cloud files keep a periodic box: CSV records it on a "# vrsph domain:" line before the
// header, VTU as field data; both read back to the same box and axes, a cloud without periodic
// axes writes no record, and a record that is malformed, of another dimension or that leaves a
// particle outside its box is an InputError naming the file (and the CSV line).
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/vtu.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// Random particles in [lo, hi) of a box that is not the unit one, periodic along `axes`.
PointCloud random_box_cloud(int dim, const std::string& axes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 lo(-0.5, 0.25, 1), hi(1.5, 0.75, 4);
  PointCloud c;
  c.dim = dim;
  c.domain = Domain::periodic_box(dim, lo, hi, axes);
  for (int i = 0; i < 40; ++i) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < dim; ++k) x[k] = lo[k] + u(rng) * (hi[k] - lo[k]);
    c.add(x, Tag::Interior);
  }
  return c;
}

void expect_same_periodic_box(const PointCloud& read, const PointCloud& written) {
  EXPECT_EQ(read.dim, written.dim);
  EXPECT_EQ(read.positions, written.positions);
  EXPECT_EQ(read.domain.shape, Domain::Shape::Box);
  EXPECT_EQ(read.domain.lo, written.domain.lo);  // 17 digits: exact
  EXPECT_EQ(read.domain.hi, written.domain.hi);
  EXPECT_EQ(read.domain.periodic, written.domain.periodic);
}

PointCloud parse_periodic_csv(const std::string& text, int dim = 0) {
  std::istringstream in(text);
  return read_csv(in, "t.csv", dim);
}

std::string periodic_scratch(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("vrsph_periodic_" + name)).string();
}
}  // namespace

TEST(PeriodicFiles, CsvKeepsTheBoxAndItsAxes) {
  for (const auto& [dim, axes] : std::vector<std::pair<int, std::string>>{{1, "x"}, {2, "x,y"}, {2, "y"}, {3, "x,z"}, {3, "all"}}) {
    const PointCloud c = random_box_cloud(dim, axes, 3);
    std::stringstream s;
    write_csv(s, c);
    EXPECT_EQ(s.str().rfind("# vrsph domain: lo=", 0), 0u) << s.str().substr(0, 80);
    const PointCloud r = read_csv(s, "mem", 0);
    expect_same_periodic_box(r, c);
    // A file path too (read_cloud_file, the CLI's and Python's reader), with its fields.
    const std::string path = periodic_scratch("cloud.csv");
    write_csv(path, c, {{"f", Field::LinSpaced(c.size(), 0, 1)}});
    const CloudFile f = read_cloud_file(path);
    expect_same_periodic_box(f.cloud, c);
    EXPECT_EQ(f.field("f", "test")[c.size() - 1], 1.0);
  }
  // A cloud without periodic axes writes no record and reads back without a domain.
  PointCloud plain = parse_periodic_csv("x,y,tag\n0,0,dirichlet\n0.5,0.5,0\n");
  std::stringstream s;
  write_csv(s, plain);
  EXPECT_EQ(s.str().rfind("x,y,z,tag", 0), 0u);
  EXPECT_FALSE(read_csv(s, "mem", 0).domain.any_periodic());
}

TEST(PeriodicFiles, CsvCommentsAreSkippedAndTheRecordSettlesTheDimension) {
  const PointCloud c = parse_periodic_csv("# made by hand\n\n# vrsph domain: lo=0,0,0 hi=1,1,1 periodic=x\n# more\nx,y,z,tag\n0.5,0.5,0,0\n");
  EXPECT_EQ(c.dim, 3);  // the record's, although z is zero everywhere
  EXPECT_EQ(c.domain.periodic_axes(), "x");
  EXPECT_EQ(parse_periodic_csv("#x,y\nx,y,tag\n0.5,0.5,0\n").dim, 2);  // a comment that looks like a header is a comment
}

TEST(PeriodicFiles, BadCsvRecordsAreNamedWithTheirLine) {
  const std::string body = "x,y,tag\n0.5,0.5,0\n";
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1\n" + body), InputError, "t.csv:1: the domain record needs lo=, hi= and periodic=");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=x size=3\n" + body), InputError,
                   "t.csv:1: the domain record takes lo=, hi= and periodic= once each, got 'size=3'");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,a hi=1,1 periodic=x\n" + body), InputError, "t.csv:1: lo= holds 'a', not a number");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0 hi=1,1 periodic=x\n" + body), InputError, "lo= has 1 numbers and hi= 2");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,0 periodic=x\n" + body), InputError,
                   "t.csv:1: domain record: periodic box: the upper corner must exceed the lower one along y");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,inf periodic=x\n" + body), InputError, "is not a finite length");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=nan,0 hi=1,1 periodic=x\n" + body), InputError,
                   "the side along x (nan .. 1) is not a finite length");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=w\n" + body), InputError, "periodic axes are x, y, z or all");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=z\n" + body), InputError, "periodic axis z does not exist in 2D");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=\n" + body), InputError, "no periodic axis");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=x\n# vrsph domain: lo=0,0 hi=1,1 periodic=y\n" + body),
                   InputError, "t.csv:2: a second domain record (the first on line 1)");
  // The record against the cloud: another dimension, a particle outside the box.
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0 hi=1 periodic=x\n" + body), InputError,
                   "t.csv: line 1 records a 1D periodic box, but the particles have 2 coordinate(s)");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0,0 hi=1,1,1 periodic=x\n" + body), InputError,
                   "t.csv: line 1 records a 3D periodic box, but the particles have only 2 coordinate(s)");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=1,1 periodic=x\nx,y,z,tag\n0.5,0.5,0,0\n", 3), InputError,
                   "t.csv: a 3D cloud, but line 1 records a 2D periodic box");
  EXPECT_THROW_MSG(parse_periodic_csv("# vrsph domain: lo=0,0 hi=0.5,1 periodic=x\nx,y,tag\n0.5,0.5,0\n"), InputError,
                   "t.csv: particle 0 at (0.5, 0.5, 0) lies outside the periodic box [0, 0.5) along x");
}

TEST(PeriodicFiles, VtuKeepsTheBoxAndItsAxes) {
  if (!built_with("VTK_XML")) GTEST_SKIP() << "built without the VTK XML reader";
  for (const auto format : {VtuFormat::Ascii, VtuFormat::Binary})
    for (const auto& [dim, axes] : std::vector<std::pair<int, std::string>>{{2, "x"}, {3, "all"}}) {
      const PointCloud c = random_box_cloud(dim, axes, 5);
      const std::string path = periodic_scratch("cloud.vtu");
      write_vtu(path, c, {}, format);
      expect_same_periodic_box(read_cloud_file(path).cloud, c);
    }
  // No record for a cloud without periodic axes.
  PointCloud plain = parse_periodic_csv("x,y,tag\n0,0,dirichlet\n0.5,0.5,0\n");
  const std::string path = periodic_scratch("plain.vtu");
  write_vtu(path, plain);
  EXPECT_FALSE(read_cloud_file(path).cloud.domain.any_periodic());
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  EXPECT_EQ(text.str().find("FieldData"), std::string::npos);
}

TEST(PeriodicFiles, VtkRewritesKeepTheBox) {
  if (!built_with("VTK_XML")) GTEST_SKIP() << "built without the VTK XML reader";
  // Our periodic VTU read and written again by VTK 9.1 itself (appended raw field data):
  // 8 x 9 particles of the unit box periodic along x (no boundary particles there).
  const PointCloud c = read_cloud_file(std::string(VRSPH_VTK_FIXTURES) + "/vtk_written_periodic.vtu").cloud;
  EXPECT_EQ(c.size(), 72);
  EXPECT_EQ(c.count(Tag::Dirichlet), 16);
  EXPECT_EQ(c.domain.periodic_axes(), "x");
  EXPECT_EQ(c.domain.lo, Vec3(0, 0, 0));
  EXPECT_EQ(c.domain.hi, Vec3(1, 1, 0));
}

TEST(PeriodicFiles, BadVtuRecordsAreNamed) {
  if (!built_with("VTK_XML")) GTEST_SKIP() << "built without the VTK XML reader";
  const auto vtu = [](const std::string& field_data) {
    const std::string path = periodic_scratch("bad.vtu");
    std::ofstream(path) << "<?xml version=\"1.0\"?><VTKFile type=\"UnstructuredGrid\" byte_order=\"LittleEndian\">"
                           "<UnstructuredGrid><FieldData>" + field_data + "</FieldData><Piece NumberOfPoints=\"2\" "
                           "NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                           "format=\"ascii\">0.25 0.5 0 0.75 0.5 0</DataArray></Points><PointData><DataArray "
                           "type=\"Int32\" Name=\"tag\" format=\"ascii\">0 0</DataArray></PointData></Piece>"
                           "</UnstructuredGrid></VTKFile>";
    return path;
  };
  const auto box = [](const std::string& values) {
    return "<DataArray type=\"Float64\" Name=\"vrsph_periodic_box\" NumberOfComponents=\"6\" format=\"ascii\">" + values +
           "</DataArray>";
  };
  const auto axes = [](const std::string& values) {
    return "<DataArray type=\"Int32\" Name=\"vrsph_periodic_axes\" NumberOfComponents=\"3\" format=\"ascii\">" + values +
           "</DataArray>";
  };
  EXPECT_EQ(read_cloud_file(vtu(box("0 0 0 1 1 0") + axes("1 0 0"))).cloud.domain.periodic_axes(), "x");
  EXPECT_THROW_MSG(read_cloud_file(vtu(box("0 0 0 1 1 0"))), InputError, "only one of vrsph_periodic_box and vrsph_periodic_axes");
  EXPECT_THROW_MSG(read_cloud_file(vtu(box("0 0 0 1 1") + axes("1 0 0"))), InputError, "vrsph_periodic_box");
  EXPECT_THROW_MSG(read_cloud_file(vtu(box("0 0 0 1 1 0") + axes("2 0 0"))), InputError, "holds 2 (0 or 1 per axis)");
  EXPECT_THROW_MSG(read_cloud_file(vtu(box("0 0 0 1 1 1") + axes("0 0 1"))), InputError, "makes axis z periodic in a 2D cloud");
  EXPECT_THROW_MSG(read_cloud_file(vtu(box("0 0 0 0.5 1 0") + axes("1 0 0"))), InputError,
                   "the recorded periodic box: particle 1 at (0.75, 0.5, 0) lies outside the periodic box [0, 0.5) along x");
}
