// SPDX-License-Identifier: BSD-3-Clause
// Gmsh meshes as clouds: MSH 4.1 and 2.2 (fixtures written by Gmsh 4.8.4 from
// gmsh/plate_with_hole.geo) give the same particles; boundary found from the elements, with
// outward normals and the kind named by the physical groups; malformed files are named.
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/gmsh_cloud.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
const std::string gmsh_dir = VRSPH_GMSH_FIXTURES;

// The unit square as two triangles (MSH 2.2, no physical groups).
const char* square22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
2
1 2 2 0 1 1 2 3
2 2 2 0 1 1 3 4
$EndElements
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}
}  // namespace

TEST(GmshCloud, Msh41And22GiveTheSameCloudWithOutwardNormalsAndPhysicalKinds) {
  const CloudFile a = read_cloud_file(gmsh_dir + "/plate_with_hole_41.msh");
  const CloudFile b = read_cloud_file(gmsh_dir + "/plate_with_hole_22.msh");
  const PointCloud& c = a.cloud;
  ASSERT_EQ(c.dim, 2);
  EXPECT_EQ(c.positions, b.cloud.positions);
  EXPECT_EQ(c.tags, b.cloud.tags);
  EXPECT_EQ(c.normals, b.cloud.normals);
  EXPECT_GT(c.count(Tag::Interior), 0);
  const Vec3 centre(0.5, 0.5, 0);
  Index hole = 0, outer = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    const Vec3& n = c.normals[si];
    const bool on_hole = std::abs((x - centre).norm() - 0.2) < 1e-6;
    const bool on_square = x.head<2>().minCoeff() < 1e-12 || x.head<2>().maxCoeff() > 1 - 1e-12;
    if (c.tags[si] == Tag::Interior) {
      EXPECT_FALSE(on_hole || on_square) << x.transpose();
      continue;
    }
    ASSERT_NEAR(n.norm(), 1, 1e-12);
    if (on_hole) {  // "hole_neumann": Neumann, normal into the hole (out of the domain)
      ++hole;
      EXPECT_EQ(c.tags[si], Tag::Neumann);
      EXPECT_LT(n.dot((x - centre).normalized()), -0.95) << x.transpose();
    } else {
      ++outer;
      ASSERT_TRUE(on_square) << x.transpose();
      EXPECT_EQ(c.tags[si], Tag::Dirichlet);
      const Vec3 expected(x[0] < 1e-12 ? -1 : x[0] > 1 - 1e-12 ? 1 : 0, x[1] < 1e-12 ? -1 : x[1] > 1 - 1e-12 ? 1 : 0, 0);
      EXPECT_NEAR((n - expected.normalized()).norm(), 0, 1e-12) << x.transpose();
    }
  }
  EXPECT_GT(hole, 4);
  EXPECT_GT(outer, 8);
}

TEST(GmshCloud, BoundaryWithoutPhysicalGroupsIsDirichletAndA3DElementWorks) {
  const CloudFile sq = parse_gmsh_cloud(square22, "sq.msh");
  EXPECT_EQ(sq.cloud.count(Tag::Dirichlet), 4);
  EXPECT_NEAR((sq.cloud.normals[0] - Vec3(-1, -1, 0).normalized()).norm(), 0, 1e-12);
  // One tetrahedron (MSH 4.1): every node on the boundary, normals pointing away from it.
  const char* tet = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 4 1 4
3 1 0 4
1
2
3
4
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
1 1 1 1
3 1 4 1
1 1 2 3 4
$EndElements
)";
  const CloudFile t = parse_gmsh_cloud(tet, "tet.msh");
  ASSERT_EQ(t.cloud.dim, 3);
  const Vec3 centroid(0.25, 0.25, 0.25);
  for (Index i = 0; i < 4; ++i) {
    const auto si = static_cast<std::size_t>(i);
    EXPECT_EQ(t.cloud.tags[si], Tag::Dirichlet);
    EXPECT_GT(t.cloud.normals[si].dot(t.cloud.positions[si] - centroid), 0);
  }
  EXPECT_THROW_MSG(parse_gmsh_cloud(tet, "tet.msh", 2), InputError, "tet.msh: a 3D mesh where a 2D cloud was asked for");
}

TEST(GmshCloud, MalformedFilesAreNamedWithTheLine) {
  EXPECT_THROW_MSG(parse_gmsh_cloud("", "e.msh"), InputError, "e.msh: not a Gmsh mesh");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "2.2 0 8", "2.2 1 8"), "b.msh"), InputError,
                   "binary .msh files are not read");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "2.2 0 8", "3.0 0 8"), "v.msh"), InputError,
                   "MSH format version 3.0 is not read");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "2 2 2 0 1 1 3 4", "2 9 2 0 1 1 3 4 1 2 3"), "o.msh"), InputError,
                   "o.msh:14: element type 9 is not supported");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "1 3 4\n$End", "1 3 7\n$End"), "u.msh"), InputError,
                   "u.msh:14: element refers to node 7, which $Nodes does not define");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "3 1 1 0", "3 1 1 0.5"), "z.msh"), InputError,
                   "z.msh: a 2D mesh must lie in the z = 0 plane");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "4 0 1 0", "4 0 x 0"), "x.msh"), InputError,
                   "x.msh:9: expected a node coordinate (a number), got 'x'");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "$Nodes\n4", "$Nodes\n4000000000"), "c.msh"), InputError,
                   "the number of nodes 4000000000 is negative or more than the rest of the file can hold");
  const std::string cut = std::string(square22).substr(0, std::string(square22).find("$EndNodes"));
  EXPECT_THROW_MSG(parse_gmsh_cloud(cut, "t.msh"), InputError, "t.msh: the file ends where $EndNodes was expected");
  EXPECT_THROW_MSG(parse_gmsh_cloud(replaced(square22, "4 0 1 0", "3 0 1 0"), "d.msh"), InputError,
                   "d.msh:9: node tag 3 defined twice");
  EXPECT_THROW_MSG(read_gmsh_cloud("/nonexistent/m.msh"), IoError, "cannot open point cloud file");
}
