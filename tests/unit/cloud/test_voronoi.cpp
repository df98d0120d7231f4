// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud perturbed_cloud(int dim, int n, std::uint64_t seed) {
  PointCloud c = cell_centred_lattice(Domain::unit_box(dim), n, false);
  perturb(c, {.delta = 0.4, .seed = seed});
  return c;
}
double sum(const std::vector<Real>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }
}  // namespace

TEST(Voronoi, LatticeCellsAreExact) {
  for (int dim = 1; dim <= 3; ++dim) {
    const PointCloud c = vertex_lattice(Domain::unit_box(dim), 6);  // spacing 1/6, particles on the faces
    const auto m = voronoi_cell_measures(c);
    const double h = 1.0 / 6;
    for (std::size_t i = 0; i < m.size(); ++i) {
      int on_faces = 0;  // a face particle's cell is halved per face it lies on
      for (int k = 0; k < dim; ++k) on_faces += c.positions[i][k] < 1e-12 || c.positions[i][k] > 1 - 1e-12;
      EXPECT_NEAR(m[i], std::pow(h, dim) / std::pow(2.0, on_faces), 1e-14) << dim << "D particle " << i;
    }
    EXPECT_NEAR(sum(m), 1.0, 1e-12);
  }
}

// The measures of a perturbed cloud against a Monte Carlo count of the points nearest to each
// particle (an independent computation), and their sum against |domain|.
TEST(Voronoi, PerturbedCellsMatchMonteCarlo) {
  for (int dim = 2; dim <= 3; ++dim) {
    const PointCloud c = perturbed_cloud(dim, dim == 2 ? 7 : 4, 3);
    const auto m = voronoi_cell_measures(c);
    EXPECT_NEAR(sum(m), 1.0, 1e-12) << dim << "D";
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    const int samples = 400000;
    std::vector<double> hits(m.size(), 0);
    for (int s = 0; s < samples; ++s) {
      Vec3 x = Vec3::Zero();
      for (int k = 0; k < dim; ++k) x[k] = u(rng);
      std::size_t best = 0;
      for (std::size_t i = 1; i < c.positions.size(); ++i)
        if ((c.positions[i] - x).squaredNorm() < (c.positions[best] - x).squaredNorm()) best = i;
      hits[best] += 1.0 / samples;
    }
    for (std::size_t i = 0; i < m.size(); ++i)  // 5 binomial standard deviations
      EXPECT_NEAR(m[i], hits[i], 5 * std::sqrt(m[i] / samples) + 1e-12) << dim << "D particle " << i;
  }
}

TEST(Voronoi, DiskCellsSumToTheDisk) {
  const PointCloud c = ball_cloud(2, 1.5, 16);
  const auto m = voronoi_cell_measures(c);
  EXPECT_NEAR(sum(m), std::numbers::pi * 2.25, 1e-11);
  for (double v : m) EXPECT_GT(v, 0);
}

TEST(Voronoi, RefusesWhatItCannotClip) {
  PointCloud c = perturbed_cloud(2, 5, 1);
  c.positions[7] = c.positions[3];
  try {
    voronoi_cell_measures(c);
    FAIL() << "coincident particles accepted";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("particles 3 and 7 coincide"), std::string::npos) << e.what();
  }
  EXPECT_THROW(voronoi_cell_measures(ball_cloud(3, 1, 6)), InputError);
  PointCloud none = perturbed_cloud(2, 4, 1);
  none.domain = Domain{};
  EXPECT_THROW(voronoi_cell_measures(none), InputError);
}
