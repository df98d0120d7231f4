// SPDX-License-Identifier: BSD-3-Clause
#include <sstream>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/csv.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud parse(const std::string& text, int dim = 0) {
  std::istringstream in(text);
  return read_csv(in, "t.csv", dim);
}
}  // namespace

TEST(Csv, RoundTripIsLossless) {
  for (int dim = 1; dim <= 3; ++dim) {
    PointCloud c = vertex_lattice(Domain::unit_box(dim), 4);
    perturb(c, {0.3, 9, false});
    std::stringstream s;
    write_csv(s, c);
    const PointCloud r = read_csv(s, "mem", 0);
    EXPECT_EQ(r.dim, dim);
    EXPECT_EQ(r.positions, c.positions);
    EXPECT_EQ(r.tags, c.tags);
    EXPECT_EQ(r.normals, c.normals);
  }
}

TEST(Csv, AcceptsColumnsInAnyOrderAndNumericTags) {
  const PointCloud c = parse("tag, y ,x\n0,0.5,1\ndirichlet,1,0\n3,2,2\n");
  EXPECT_EQ(c.dim, 2);
  EXPECT_EQ(c.positions[0], Vec3(1, 0.5, 0));
  EXPECT_EQ(c.tags[1], Tag::Dirichlet);
  EXPECT_EQ(c.tags[2], Tag::Ghost);
  EXPECT_EQ(parse("x,y,z,tag\n1,2,0,0\n", 0).dim, 2);  // z identically zero
  EXPECT_EQ(parse("x,y,z,tag\n1,2,0,0\n", 3).dim, 3);  // explicitly 3D
}

TEST(Csv, MalformedInputIsReportedWithLineNumbers) {
  EXPECT_THROW_MSG(parse(""), InputError, "t.csv: empty file");
  EXPECT_THROW_MSG(parse("x,y\n1,2\n"), InputError, "at least the columns x and tag");
  EXPECT_THROW_MSG(parse("x,y,,tag\n"), InputError, "column 3 of the header has no name");
  EXPECT_THROW_MSG(parse("x,y,w,tag\n1,2,abc,0\n"), InputError, "t.csv:2: column w: 'abc' is not a number");
  EXPECT_THROW_MSG(parse("x,tag\n"), InputError, "no particles after the header");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,2,0\n1,0\n"), InputError, "t.csv:3: expected 3 fields, found 2");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,abc,0\n"), InputError, "t.csv:2: column y: 'abc' is not a number");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,nan,0\n"), InputError, "column y is not finite");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,inf,0\n"), InputError, "column y is not finite");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,1,wall\n"), InputError, "t.csv:2: unknown particle tag 'wall'");
  EXPECT_THROW_MSG(parse("x,y,z,tag\n1,1,1,0\n", 2), InputError, "dimension mismatch: 2D requested but coordinate z");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,1,0\n", 3), InputError, "dimension mismatch: 3D requested but the file has only 2");
  EXPECT_THROW_MSG(parse("x,y,tag\n1,1,neumann\n"), InputError, "Neumann particle 0");
  EXPECT_THROW_MSG(read_csv("/nonexistent/cloud.csv"), InputError, "cannot open point cloud file '/nonexistent/cloud.csv'");
}

TEST(Csv, ExtraColumnsAreFields) {
  std::istringstream in("x,y,Tag,Coef,rhs\n0,0,dirichlet,1.5,-2\n0.5,0.5,interior,2.5,3e-1\n");
  const CloudFile f = read_csv_with_fields(in, "t.csv");
  EXPECT_EQ(f.cloud.size(), 2);
  ASSERT_EQ(f.fields.size(), 2u);
  EXPECT_EQ(f.fields[0].name, "coef");  // names are case-insensitive, kept lower case
  EXPECT_EQ(f.field("COEF", "--a-column")[1], 2.5);
  EXPECT_EQ(f.field("rhs", "--f-column")[0], -2.0);
  EXPECT_THROW_MSG((void)f.field("g", "--g-column"), InputError,
                   "t.csv: no column 'g' for --g-column (the file's extra columns: coef, rhs)");
  std::istringstream plain("x,y,tag\n0,0,0\n");
  EXPECT_TRUE(read_csv_with_fields(plain, "p.csv").fields.empty());
}
