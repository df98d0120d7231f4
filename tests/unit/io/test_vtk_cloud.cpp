// SPDX-License-Identifier: BSD-3-Clause
// VTK XML clouds (.vtu/.vtp) in every encoding the format has (fixtures written by
// vtk/make_fixtures.py, and vtk_written_* by VTK 9.1's own writers from ascii.vtu): all must
// give the same cloud and field as the ascii file.
#include <filesystem>
#include <fstream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/vtk_cloud.hpp>
#include <vrsph/io/vtu.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
const std::string dir = VRSPH_VTK_FIXTURES;

std::string scratch(const std::string& name, const std::string& text) {
  const auto path = (std::filesystem::temp_directory_path() / ("vrsph_vtk_" + name)).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// A minimal ascii .vtu around the given point-data arrays.
std::string vtu(const std::string& point_data, const std::string& root_attrs = "") {
  return "<?xml version=\"1.0\"?><VTKFile type=\"UnstructuredGrid\" byte_order=\"LittleEndian\"" + root_attrs +
         "><UnstructuredGrid><Piece NumberOfPoints=\"2\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" "
         "NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0</DataArray></Points><PointData>" +
         point_data + "</PointData></Piece></UnstructuredGrid></VTKFile>";
}
}  // namespace

TEST(VtkCloud, EveryEncodingGivesTheSameCloud) {
  const CloudFile ref = read_cloud_file(dir + "/ascii.vtu");
  EXPECT_EQ(ref.cloud.dim, 2);
  EXPECT_EQ(ref.cloud.size(), 12);
  EXPECT_EQ(ref.cloud.count(Tag::Neumann), 1);
  EXPECT_EQ(ref.cloud.normals[4], Vec3(-1, 0, 0));
  EXPECT_NEAR(ref.field("k", "test")[5], 1 + 0.25 * 0.25 + 2 * 0.5, 1e-6);
  for (const char* name : {"binary32.vtu", "binary64_zlib.vtu", "appended_raw.vtu", "appended_raw_zlib.vtu",
                           "appended_base64.vtu", "appended_base64_zlib.vtu", "binary32.vtp",
                           // written by VTK 9.1 itself (python3-vtk9) from ascii.vtu:
                           "vtk_written_appended_zlib.vtu", "vtk_written_binary.vtu", "vtk_written_appended_raw.vtu",
                           "vtk_written_binary_zlib.vtu", "vtk_written_poly.vtp"}) {
    const CloudFile f = read_cloud_file(dir + "/" + name);
    EXPECT_EQ(f.cloud.positions, ref.cloud.positions) << name;
    EXPECT_EQ(f.cloud.tags, ref.cloud.tags) << name;
    EXPECT_EQ(f.cloud.normals, ref.cloud.normals) << name;
    EXPECT_EQ(f.field("K", "test"), ref.field("k", "test")) << name;
  }
}

TEST(VtkCloud, OurOwnVtuReadsBack) {
  PointCloud c;
  c.dim = 3;
  c.add(Vec3(0, 0, 0), Tag::Dirichlet);
  c.add(Vec3(0.5, 0.25, 0.125), Tag::Interior);
  c.add(Vec3(1, 1, 1), Tag::Ghost);
  Eigen::MatrixXd u(3, 1);
  u << 1, 2, 3;
  const std::string path = (std::filesystem::temp_directory_path() / "vrsph_vtk_roundtrip.vtu").string();
  write_vtu(path, c, {{"u", u}});
  const CloudFile f = read_cloud_file(path);
  EXPECT_EQ(f.cloud.positions, c.positions);
  EXPECT_EQ(f.cloud.tags, c.tags);
  EXPECT_EQ(f.field("u", "test")[2], 3.0);
}

TEST(VtkCloud, BadFilesAreNamed) {
  const std::string tag = "<DataArray type=\"Int32\" Name=\"tag\" format=\"ascii\">1 1</DataArray>";
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("not_xml.vtu", "x,y,tag\n")), InputError, "not a VTK XML file");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("no_tag.vtu", vtu(""))), InputError, "no point-data array 'tag'");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("bad_tag.vtu", vtu("<DataArray type=\"Int32\" Name=\"tag\" format=\"ascii\">1 7</DataArray>"))),
                   InputError, "tag value 7 is not 0");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("short.vtu", vtu("<DataArray type=\"Int32\" Name=\"tag\" format=\"ascii\">1</DataArray>"))),
                   InputError, "expected 2 values in 1 characters");
  std::string big = vtu(tag);
  big.replace(big.find("LittleEndian"), 12, "BigEndian");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("big.vtu", big)), InputError, "big-endian VTK data are not supported");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("lz4.vtu", vtu(tag, " compressor=\"vtkLZ4DataCompressor\""))), InputError,
                   "compressor 'vtkLZ4DataCompressor' is not supported");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("b64.vtu", vtu("<DataArray type=\"Int32\" Name=\"tag\" format=\"binary\">AA*A</DataArray>"))),
                   InputError, "invalid character '*' in base64 data");
  std::string appended = vtu("<DataArray type=\"Int32\" Name=\"tag\" format=\"appended\" offset=\"0\"/>");
  appended.replace(appended.find("</VTKFile>"), 10, "<AppendedData encoding=\"raw\">_\x10");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("app.vtu", appended)), InputError, "appended data block header is truncated");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("image.vtu", "<VTKFile type=\"ImageData\"></VTKFile>")), InputError,
                   "VTK file type 'ImageData' is not supported");
  EXPECT_THROW_MSG(read_vtk_cloud(dir + "/missing.vtu"), IoError, "cannot open point cloud file");
  // A huge NumberOfPoints with little data: refused before anything that size is allocated.
  std::string huge = vtu(tag);
  huge.replace(huge.find("NumberOfPoints=\"2\""), 18, "NumberOfPoints=\"900000000000\"");
  EXPECT_THROW_MSG(read_vtk_cloud(scratch("huge.vtu", huge)), InputError, "expected 2700000000000 values in");
}
