// SPDX-License-Identifier: BSD-3-Clause
#include <numeric>
#include <vrsph/analysis/voronoi_deviation.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud perturbed(int dim, int n, double delta = 0.25) {
  PointCloud c = cell_centred_lattice(Domain::unit_box(dim), n, false);
  perturb(c, {.delta = delta, .seed = 5});
  return c;
}
std::vector<Real> uniform_volumes(const PointCloud& c) {
  return std::vector<Real>(c.positions.size(), c.domain.measure() / static_cast<Real>(c.size()));
}
}  // namespace

TEST(VoronoiDeviation, ZeroForVoronoiVolumes) {
  for (int dim = 1; dim <= 3; ++dim) {
    const PointCloud c = perturbed(dim, dim == 1 ? 40 : dim == 2 ? 12 : 5);
    const auto cells = voronoi_cell_measures(c);
    const auto d = voronoi_deviation(c, cells, cells);
    EXPECT_NEAR(d.value, 0, 1e-12) << dim << "D";
  }
}

// The pair radius only restricts the LP: on small sets (N = 256) the default 2 dx must give
// the unrestricted minimum, and the block decomposition an upper bound not far above it.
TEST(VoronoiDeviation, RestrictedAndBlockBoundsAgainstTheFullLp) {
  const PointCloud c = perturbed(2, 16);  // N = 256
  const auto cells = voronoi_cell_measures(c);
  const auto V = uniform_volumes(c);
  VoronoiDeviationOptions full;
  full.radius = 10;  // every pair
  const auto exact = voronoi_deviation(c, V, cells, full);
  EXPECT_EQ(exact.method, "lp");
  EXPECT_FALSE(exact.is_upper_bound);
  EXPECT_EQ(exact.variables, 256 * 256 + 1);
  const auto restricted = voronoi_deviation(c, V, cells);
  EXPECT_TRUE(restricted.is_upper_bound);
  EXPECT_NEAR(restricted.value, exact.value, 1e-6 * exact.value);
  EXPECT_GT(exact.value, 0.05 / 16);  // delta 1/4: cells differ from dx^2 by tens of percent
  VoronoiDeviationOptions split;
  split.direct_limit = 100;
  split.block_particles = 64;
  const auto blocks = voronoi_deviation(c, V, cells, split);
  EXPECT_EQ(blocks.method, "lp-blocks");
  EXPECT_EQ(blocks.blocks, 4);
  EXPECT_GE(blocks.value, exact.value * (1 - 1e-9));
  EXPECT_LE(blocks.value, 2 * exact.value);
}

TEST(VoronoiDeviation, VolumesMustSumToTheDomain) {
  const PointCloud c = perturbed(2, 8);
  const auto cells = voronoi_cell_measures(c);
  auto V = uniform_volumes(c);
  for (auto& v : V) v *= 1.01;
  try {
    voronoi_deviation(c, V, cells);
    FAIL() << "mismatched volumes accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("normalise-volumes"), std::string::npos) << e.what();
  }
  VoronoiDeviationOptions o;
  o.normalise_volumes = true;
  const auto d = voronoi_deviation(c, V, cells, o);
  EXPECT_TRUE(d.volumes_normalised);
  EXPECT_NEAR(d.value, voronoi_deviation(c, uniform_volumes(c), cells).value, 1e-9);
  V.pop_back();
  EXPECT_THROW(voronoi_deviation(c, V, cells), InputError);
}

// The potential flow is one decomposition, not the minimum: an upper bound on the full LP's
// d_N, 0 for Voronoi volumes, and (measured on these sets) not far above the LP's bound.
// Auto takes it above flow_above particles and falls back on the LP where it cannot carry
// the surplus (layout A: halved face cells).
TEST(VoronoiDeviation, PotentialFlowIsAnUpperBoundAndAutoFallsBackOnTheLp) {
  const PointCloud c = perturbed(2, 16);
  const auto cells = voronoi_cell_measures(c);
  const auto V = uniform_volumes(c);
  VoronoiDeviationOptions full;
  full.radius = 10;
  const Real exact = voronoi_deviation(c, V, cells, full).value;
  VoronoiDeviationOptions flow;
  flow.method = DeviationMethod::Flow;
  const auto f = voronoi_deviation(c, V, cells, flow);
  EXPECT_EQ(f.method, "potential-flow");
  EXPECT_TRUE(f.is_upper_bound);
  EXPECT_GE(f.value, exact * (1 - 1e-9));
  EXPECT_LE(f.value, 1.5 * exact);
  EXPECT_NEAR(voronoi_deviation(c, cells, cells, flow).value, 0, 1e-12);
  for (int dim : {1, 3}) {
    const PointCloud d = perturbed(dim, dim == 1 ? 60 : 5);
    const auto dc = voronoi_cell_measures(d);
    EXPECT_GE(voronoi_deviation(d, uniform_volumes(d), dc, flow).value,
              voronoi_deviation(d, uniform_volumes(d), dc).value * (1 - 1e-9)) << dim << "D";
  }
  VoronoiDeviationOptions automatic;
  automatic.flow_above = 100;
  EXPECT_EQ(voronoi_deviation(c, V, cells, automatic).method, "potential-flow");
  automatic.flow_above = 1000;
  EXPECT_EQ(voronoi_deviation(c, V, cells, automatic).method, "lp-restricted");
  PointCloud a = vertex_lattice(Domain::unit_box(2), 24);
  perturb(a, {.delta = 0.5, .seed = 3});
  const auto ac = voronoi_cell_measures(a);
  automatic.flow_above = 100;
  EXPECT_NE(voronoi_deviation(a, uniform_volumes(a), ac, automatic).method, "potential-flow");
  EXPECT_THROW_MSG(voronoi_deviation(a, uniform_volumes(a), ac, flow), NumericalError, "use --dn-method lp");
  EXPECT_THROW_MSG(parse_deviation_method("simplex"), ConfigError, "known: auto, lp, flow");
}
