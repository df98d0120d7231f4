// SPDX-License-Identifier: BSD-3-Clause
// The optional parts: a feature of a part the build has works, one of a part it lacks throws
// FeatureUnavailable naming the part and the CMake option (never a link error or a crash).
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/analysis/voronoi_deviation.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/config.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/io/vtk_cloud.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/solve/solver.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// Runs `feature`; in a build with `part` it must not throw FeatureUnavailable (it may throw
// another error on the deliberately tiny input), without it it must, with the rebuild hint.
template <class F>
void expect_part(const char* part, F feature) {
  try {
    feature();
    EXPECT_TRUE(built_with(part)) << part << ": the feature ran in a build without it";
  } catch (const FeatureUnavailable& e) {
    EXPECT_FALSE(built_with(part)) << part << ": " << e.what();
    const std::string msg = e.what();
    EXPECT_NE(msg.find(std::string("vrsph was built without ") + part), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::string("-DVRSPH_WITH_") + part + "=ON"), std::string::npos) << msg;
    EXPECT_NE(msg.find("apt-get install"), std::string::npos) << msg;
  } catch (const std::exception&) {
    EXPECT_TRUE(built_with(part)) << part << ": another error than FeatureUnavailable without the part";
  }
}

CsrMatrix identity(Index n) {
  CsrMatrix A(n, n);
  A.setIdentity();
  return A;
}
}  // namespace

TEST(Features, PartsListMatchesTheGeneratedConfiguration) {
  EXPECT_EQ(built_with("PETSC"), VRSPH_HAVE_PETSC != 0);
  EXPECT_EQ(built_with("MPI"), VRSPH_HAVE_MPI != 0);
  EXPECT_EQ(built_with("CGAL"), VRSPH_HAVE_CGAL != 0);
  EXPECT_EQ(built_with("CLP"), VRSPH_HAVE_CLP != 0);
  EXPECT_EQ(built_with("SUITESPARSE"), VRSPH_HAVE_SUITESPARSE != 0);
  EXPECT_EQ(built_with("MUPARSER"), VRSPH_HAVE_MUPARSER != 0);
  EXPECT_EQ(built_with("VTK_XML"), VRSPH_HAVE_VTK_XML != 0);
  EXPECT_EQ(built_with("JSON"), VRSPH_HAVE_JSON != 0);
  EXPECT_EQ(built_with("TOML"), VRSPH_HAVE_TOML != 0);
  EXPECT_FALSE(built_with("NOPE"));
  EXPECT_EQ(parts().size(), 10u);
  for (const Part& p : parts()) EXPECT_FALSE(p.licence.empty() || p.packages.empty()) << p.name;
  EXPECT_EQ(version(), VRSPH_VERSION_STRING);
  EXPECT_EQ(VRSPH_HAVE_PETSC, VRSPH_HAVE_MPI);  // configured together (cmake/vrsph_parts.cmake)
}

TEST(Features, EachFeatureWorksOrSaysWhichPartIsMissing) {
  expect_part("PETSC", [] {
    SolverOptions o;
    o.type = SolverType::Petsc;
    PreparedSolver s(identity(4), o);
  });
  expect_part("SUITESPARSE", [] {
    SolverOptions o;
    o.type = SolverType::UmfPack;
    PreparedSolver s(identity(4), o);
  });
  expect_part("CGAL", [] { (void)mesh_centroids(Domain::unit_box(2), 0.25, 1, 0, false); });
  expect_part("CGAL", [] { (void)read_closed_surface("/nonexistent/solid.stl"); });
  expect_part("MUPARSER", [] { (void)make_expression_function("x*y", 2); });
  expect_part("VTK_XML", [] { (void)parse_vtk_cloud("<VTKFile/>", "tiny.vtu"); });
  expect_part("JSON", [] { (void)parse_geojson_polygon(R"({"type": "Polygon"})", "tiny.geojson"); });
  expect_part("CLP", [] {
    const PointCloud c = cell_centred_lattice(Domain::unit_box(1), 8, false, 0);
    const std::vector<Real> v(8, 0.125);
    VoronoiDeviationOptions o;
    o.method = DeviationMethod::Lp;
    (void)voronoi_deviation(c, v, v, o);
  });
}

TEST(Features, AutoChoosesSolversThisBuildHas) {
  EXPECT_EQ(auto_direct_solver(), built_with("SUITESPARSE") ? SolverType::UmfPack : SolverType::SparseLU);
  EXPECT_EQ(resolve_auto(10, 2), auto_direct_solver());
  EXPECT_EQ(resolve_auto(1000000, 2), built_with("PETSC") ? SolverType::Petsc : SolverType::BiCGSTAB);
  // A solve through auto works in every build.
  LinearSystem sys;
  sys.A = identity(5);
  sys.b = Eigen::VectorXd::Ones(5);
  sys.particle_of_dof = {0, 1, 2, 3, 4};
  Eigen::VectorXd x;
  const SolveReport r = solve(sys, x, {});
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_NEAR(x.sum(), 5.0, 1e-12);
}

TEST(Features, WorldIsSerialWithoutMpiUnlessLaunchedInParallel) {
  if (built_with("MPI")) GTEST_SKIP() << "the MPI tests cover world() (tests/mpi)";
  EXPECT_EQ(Communicator::world().size(), 1);
  EXPECT_DOUBLE_EQ(sum_over_ranks(Communicator{}, 2.5), 2.5);
}
