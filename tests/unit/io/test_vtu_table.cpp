// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/vtu.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(Vtu, WritesPointsTagsAndFields) {
  const PointCloud c = vertex_lattice(Domain::unit_box(2), 3);
  Eigen::MatrixXd s = Eigen::MatrixXd::Constant(c.size(), 1, 2.5), g = Eigen::MatrixXd::Ones(c.size(), 2);
  const std::string path = ::testing::TempDir() + "/vrsph_test.vtu";
  write_vtu(path, c, {{"U", s}, {"grad", g}});
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string t = text.str();
  EXPECT_NE(t.find("NumberOfPoints=\"16\""), std::string::npos);
  EXPECT_NE(t.find("Name=\"U\""), std::string::npos);
  EXPECT_NE(t.find("Name=\"grad\" NumberOfComponents=\"3\""), std::string::npos);
  EXPECT_NE(t.find("</VTKFile>"), std::string::npos);
  std::remove(path.c_str());
  EXPECT_THROW_MSG(write_vtu(path, c, {{"bad", Eigen::MatrixXd::Zero(3, 1)}}), InputError, "VTU field 'bad' has 3 rows");
  EXPECT_THROW_MSG(write_vtu(path, c, {{"a<b", s}}), InputError, "contains a quote or <, >, &");
}

TEST(Vtu, BinaryAndAsciiReadBackExactly) {
  VRSPH_REQUIRE_PART("VTK_XML");  // reading back; tests/cli/test_parts.py decodes the output of every build
  PointCloud c = vertex_lattice(Domain::unit_box(3), 5);
  perturb(c, {0.4, 3, false});
  Eigen::MatrixXd u(c.size(), 1), g(c.size(), 3);
  for (Index i = 0; i < c.size(); ++i) {
    u(i, 0) = std::sin(1 + static_cast<Real>(i));
    g.row(i) = c.positions[static_cast<std::size_t>(i)].transpose() / 3;
  }
  for (const VtuFormat f : {VtuFormat::Binary, VtuFormat::Ascii}) {
    const std::string path = ::testing::TempDir() + "/vrsph_round_trip.vtu";
    write_vtu(path, c, {{"u", u}, {"g", g}}, f);
    const CloudFile r = read_cloud_file(path);
    EXPECT_EQ(r.cloud.positions, c.positions);
    EXPECT_EQ(r.cloud.tags, c.tags);
    EXPECT_EQ(r.cloud.normals, c.normals);
    EXPECT_EQ(r.field("u", "test"), u.col(0));
    std::remove(path.c_str());
  }
}

TEST(Table, FormatsMarkdownCsvAndJson) {
  Table t;
  t.columns = {"n", "error", "order"};
  t.add_row({{"n", 8LL}, {"error", 0.5}, {"order", std::nan("")}});
  t.add_row({{"n", 16LL}, {"error", 0.125}, {"order", 2.0}});
  EXPECT_NE(to_markdown(t).find("| 16 | 1.2500e-01 | 2.0000e+00 |"), std::string::npos);
  EXPECT_NE(to_csv(t).find("8,0.5,\n"), std::string::npos);
  const std::string j = to_json(t, Json::object({{"problem", "x"}}));
  EXPECT_NE(j.find("\"problem\": \"x\""), std::string::npos);
  EXPECT_NE(j.find("\"order\": null"), std::string::npos);
  EXPECT_THROW_MSG(to_json(t, Json("x")), ConfigError, "must be an object");
  EXPECT_THROW_MSG(parse_table_format("xml"), ConfigError, "unknown output format 'xml'");
  EXPECT_THROW_MSG(t.add_row({{"nope", 1LL}}), ConfigError, "no column 'nope'");
}
