// SPDX-License-Identifier: BSD-3-Clause
// One test per class of hostile input found by the reliability probe (issue 9):
// extreme extents for the neighbour search, NUL bytes and byte-order marks, write
// errors, memory estimates, strict numbers, and the pure-Neumann solvability check.
#include <cmath>
#include <sstream>
#include <vrsph/analysis/compatibility.hpp>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/reproduce/spectrum.hpp>
#include <vrsph/solve/solver.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/neighbours/brute_force.hpp>
#include <vrsph/neighbours/search.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// Restores the process-wide memory limit when a test ends.
struct MemoryLimit {
  std::size_t saved = memory_limit_bytes();
  explicit MemoryLimit(std::size_t bytes) { set_memory_limit_bytes(bytes); }
  ~MemoryLimit() { set_memory_limit_bytes(saved); }
};

PointCloud cloud_of(const std::vector<Vec3>& points, int dim = 2) {
  PointCloud c;
  c.dim = dim;
  for (const auto& x : points) c.add(x, Tag::Interior);
  return c;
}
}  // namespace

// The cell list counted cells in integers: an extent 1e12 times the radius overflowed
// (heap writes past the end). Any finite extent must now give the brute-force answer.
TEST(HostileInput, NeighbourSearchHandlesAnyFiniteExtent) {
  for (const Real far : {1e6, 1e12, 1e100, 1e149}) {
    std::vector<Vec3> pts;
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) pts.emplace_back(0.1 * i, 0.1 * j, 0);
    pts.emplace_back(far, far, 0);
    pts.emplace_back(far * (1 + 1e-15) + 0.05, far, 0);
    const PointCloud c = cloud_of(pts);
    SearchParams sp;
    sp.radius = 0.15;
    sp.min_neighbours = 0;
    const NeighbourList fast = find_neighbours(c, sp), ref = find_neighbours_brute_force(c, sp);
    EXPECT_EQ(fast.offsets, ref.offsets) << "far = " << far;
    EXPECT_EQ(fast.indices, ref.indices) << "far = " << far;
    EXPECT_EQ(fast.count(0), 3) << "corner particle keeps its lattice neighbours, far = " << far;
  }
}

TEST(HostileInput, TinyRadiusIsolatesParticlesWithoutOverflow) {
  const PointCloud c = vertex_lattice(Domain::unit_box(3), 10);
  SearchParams sp;
  sp.radius = 1e-13;
  EXPECT_THROW_MSG(find_neighbours(c, sp), GeometryError, "has 0 neighbours within radius 1e-13");
  sp.min_neighbours = 0;
  EXPECT_EQ(find_neighbours(c, sp).indices.size(), 0u);
}

TEST(HostileInput, CoordinatesBeyondSquareableRangeAreRefused) {
  const PointCloud c = cloud_of({Vec3(0, 0, 0), Vec3(1e200, 0, 0)});
  EXPECT_THROW_MSG(validate(c), InputError, "beyond +-1e+150");
  EXPECT_NO_THROW(validate(cloud_of({Vec3(0, 0, 0), Vec3(1e150, -1e150, 0)})));
}

TEST(HostileInput, DegenerateCloudsHaveTheirOwnMessages) {
  EXPECT_THROW_MSG(estimate_spacing(cloud_of({Vec3(0.5, 0.5, 0)})), GeometryError, "only 1 particle");
  EXPECT_THROW_MSG(estimate_spacing(cloud_of({Vec3(1, 2, 0), Vec3(1, 2, 0), Vec3(1, 2, 0)})), GeometryError,
                   "all 3 particles are at the same position");
}

TEST(HostileInput, CsvNulByteBomAndDirectory) {
  std::istringstream nul(std::string("x,y,tag\n0,0,interior\n0.5\0" "7,0.25,interior\n", 41));
  EXPECT_THROW_MSG(read_csv(nul, "t.csv"), InputError, "t.csv:3: contains a NUL byte");
  std::istringstream bom("\xEF\xBB\xBFx,y,tag\n0,0,interior\n1,1,dirichlet\n");
  EXPECT_EQ(read_csv(bom, "b.csv").size(), 2);
  EXPECT_THROW_MSG(read_csv(std::string("/tmp"), 2), IoError, "is a directory");
  std::istringstream junk("x,y,tag\n0,0.5abc,interior\n");
  EXPECT_THROW_MSG(read_csv(junk, "j.csv"), InputError, "'0.5abc' is not a number");
}

TEST(HostileInput, WriteErrorsAreNeverSilent) {
  const PointCloud c = vertex_lattice(Domain::unit_box(2), 4);
  EXPECT_THROW_MSG(write_csv("/dev/full", c), IoError, "No space left on device");
  EXPECT_THROW_MSG(write_vtu("/dev/full", c, {}), IoError, "No space left on device");
  EXPECT_THROW_MSG(write_csv("/nonexistent-dir/c.csv", c), IoError, "cannot open point cloud file");
  EXPECT_THROW_MSG(write_csv("/tmp", c), IoError, "is a directory");
}

// Refused from an estimate before allocating, with the estimate and the limit.
TEST(HostileInput, MemoryEstimatesRefuseOversizedRuns) {
  {
    const MemoryLimit limit(1 << 20);
    EXPECT_THROW_MSG(vertex_lattice(Domain::unit_box(3), 200), ResourceError, "the point cloud (");
  }
  const PointCloud big = vertex_lattice(Domain::unit_box(2), 200);
  SearchParams sp;
  sp.radius = 0.2;  // ~500 neighbours each: 20M pairs, ~240 MB
  {
    const MemoryLimit limit(64u << 20);
    EXPECT_THROW_MSG(find_neighbours(big, sp), ResourceError, "estimated from 64 particles");
  }
  const PointCloud small = vertex_lattice(Domain::unit_box(2), 100);  // below the sampling threshold: exact count
  {
    const MemoryLimit limit(1u << 20);
    EXPECT_THROW_MSG(find_neighbours(small, sp), ResourceError, "more than the memory limit of 1 MiB");
  }
  EXPECT_EQ(parse_memory_size("8G"), 8ull << 30);
  EXPECT_EQ(parse_memory_size("512m"), 512ull << 20);
  EXPECT_EQ(parse_memory_size("0"), 0u);
  EXPECT_THROW_MSG(parse_memory_size("lots"), ConfigError, "not understood");
  EXPECT_THROW_MSG(parse_memory_size("-1G"), ConfigError, "not understood");
}

TEST(HostileInput, StrictNumbers) {
  EXPECT_EQ(parse_real(" 2.5e-3 "), 2.5e-3);
  EXPECT_FALSE(parse_real("2.5x").has_value());
  EXPECT_FALSE(parse_real(std::string("2.5\0" "1", 4)).has_value());
  EXPECT_FALSE(parse_real("").has_value());
  EXPECT_EQ(parse_integer("-42"), -42);
  EXPECT_FALSE(parse_integer("1e3").has_value());
  EXPECT_FALSE(parse_integer("99999999999999999999999").has_value());
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
  const MethodOptions o = MethodOptions::parse({"t=nan", "i=1e30", "j=7", "k=-3"});
  EXPECT_THROW_MSG(o.get_real("t", 1), ConfigError, "t='nan' is not finite");
  EXPECT_THROW_MSG(o.get_int("i", 1, 1, 100), ConfigError, "i='1e30' is not an integer");
  EXPECT_EQ(o.get_int("j", 1, 1, 100), 7);
  EXPECT_THROW_MSG(o.get_int("k", 1, 1, 100), ConfigError, "k=-3 is out of range (1 to 100)");
  // One boolean vocabulary for method options and boolean CLI options.
  for (const char* yes : {"true", "1", "yes", "on"}) EXPECT_EQ(parse_boolean(yes), true) << yes;
  for (const char* no : {"false", "0", "no", "off"}) EXPECT_EQ(parse_boolean(no), false) << no;
  for (const char* neither : {"", "TRUE", "1e300", "2", " yes", "y"}) EXPECT_FALSE(parse_boolean(neither).has_value()) << neither;
  const MethodOptions b = MethodOptions::parse({"p=on", "q=1e300"});
  EXPECT_TRUE(b.get_bool("p", false));
  EXPECT_THROW_MSG(b.get_bool("q", false), ConfigError, "q='1e300' is not a boolean");
}

// The divergence theorem in every dimension and on both domain shapes:
// u = e^x (sin y in 2D/3D) (+ z^2 in 3D) gives f = Δu and q = ∇u·n that balance;
// a constant flux q = 5 does not.
TEST(HostileInput, NeumannCompatibilityByQuadrature) {
  for (int dim = 1; dim <= 3; ++dim) {
    const auto grad = [dim](const Vec3& x) {
      if (dim == 1) return Vec3(std::exp(x[0]), 0, 0);
      return Vec3(std::exp(x[0]) * std::sin(x[1]), std::exp(x[0]) * std::cos(x[1]), dim == 3 ? 2 * x[2] : 0.0);
    };
    const auto f = [dim](const Vec3& x) { return dim == 1 ? std::exp(x[0]) : dim == 2 ? 0.0 : 2.0; };
    const auto q = [&](const Vec3& x, const Vec3& n) { return grad(x).dot(n); };
    for (const Domain& d : {Domain::unit_box(dim), Domain::ball(dim, Vec3::Zero(), 0.7)}) {
      const NeumannBalance ok = neumann_balance(d, f, q);
      EXPECT_TRUE(ok.compatible()) << "dim " << dim << ": flux " << ok.flux << " source " << ok.source;
      EXPECT_NEAR(ok.flux, ok.source, 1e-9 * std::max(1.0, ok.scale)) << "dim " << dim;
      const NeumannBalance bad = neumann_balance(d, f, [](const Vec3&, const Vec3&) { return 5.0; });
      EXPECT_FALSE(bad.compatible()) << "dim " << dim;
    }
  }
}

// Whole-run and solver estimates: refused before anything is generated or factorised.
TEST(HostileInput, RunFootprintAndSolverEstimates) {
  const RunFootprint f2 = estimate_run_footprint(2, 1e6, 3, 1, true);
  EXPECT_NEAR(f2.neighbours_per_particle, 28.27, 0.01);  // pi 3^2 lattice points in the support
  EXPECT_GT(f2.bytes, 1e9);
  EXPECT_LT(estimate_run_footprint(3, 1e6, 3, 1, false).bytes, estimate_run_footprint(3, 1e6, 3, 1, true).bytes);
  {
    const MemoryLimit limit(64u << 20);
    EXPECT_THROW_MSG(check_run_footprint(f2, "n = 1000"), ResourceError, "the run at n = 1000 (about 1000000 particles");
    EXPECT_THROW_MSG(check_spectrum_size(4000), ResourceError, "the dense eigenvalue problem (3999 unknowns)");
  }
  EXPECT_THROW_MSG(check_spectrum_size(2), ConfigError, "outside 3..5000");
  // LU fill grows faster than the matrix: 2D N^(1/3), 3D N^(2/3) per nonzero.
  Eigen::SparseMatrix<Real> a(1000000, 1000000);
  a.setIdentity();
  EXPECT_GT(direct_solver_bytes(a, 3), direct_solver_bytes(a, 2));
  EXPECT_GT(direct_solver_bytes(a, 2), direct_solver_bytes(a, 1));
}
