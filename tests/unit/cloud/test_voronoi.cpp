// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vrsph/cloud/generate.hpp>
#include <string>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
PointCloud perturbed_cloud(int dim, int n, std::uint64_t seed) {
  PointCloud c = cell_centred_lattice(Domain::unit_box(dim), n, false);
  perturb(c, {.delta = 0.4, .seed = seed});
  return c;
}
double sum(const std::vector<Real>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// The share of `samples` uniform points of the unit box nearest to each particle (an independent
// computation of the cells' measures), distances taken to the nearest image along the cloud's
// periodic axes (period 1).
std::vector<double> monte_carlo_cells(const PointCloud& c, int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> hits(c.positions.size(), 0);
  for (int s = 0; s < samples; ++s) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < c.dim; ++k) x[k] = u(rng);
    std::size_t best = 0;
    double best_d = 1e300;
    for (std::size_t i = 0; i < c.positions.size(); ++i) {
      Vec3 d = c.positions[i] - x;
      for (int k = 0; k < c.dim; ++k)
        if (c.domain.periodic[static_cast<std::size_t>(k)]) d[k] -= std::round(d[k]);
      if (d.squaredNorm() < best_d) best_d = d.squaredNorm(), best = i;
    }
    hits[best] += 1.0 / samples;
  }
  return hits;
}

// Each measure within 5 binomial standard deviations of its Monte Carlo share.
void expect_monte_carlo(const PointCloud& c, const std::vector<Real>& m, int samples, std::uint64_t seed,
                        const std::string& what) {
  const std::vector<double> hits = monte_carlo_cells(c, samples, seed);
  for (std::size_t i = 0; i < m.size(); ++i)
    EXPECT_NEAR(m[i], hits[i], 5 * std::sqrt(m[i] / samples) + 1e-12) << what << " particle " << i;
}
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
    expect_monte_carlo(c, m, 400000, 11, std::to_string(dim) + "D");
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

// A box periodic along some axes: the cells of the periodic tessellation, against a Monte Carlo
// count with minimum-image distances; unchanged when the cloud is moved along the periodic axes
// (a cell cut by a face becomes an interior one); an image near the box (as periodic_stencil's
// extended clouds hold) has its original's cell.
TEST(Voronoi, PeriodicCellsMatchMonteCarloAndMoveWithTheCloud) {
  for (const auto& [dim, axes] : {std::pair{2, "x,y"}, std::pair{2, "x"}, std::pair{3, "x,z"}, std::pair{3, "all"}}) {
    PointCloud c = perturbed_cloud(dim, dim == 2 ? 7 : 4, 5);
    c.domain.set_periodic(axes);
    const auto m = voronoi_cell_measures(c);
    EXPECT_NEAR(sum(m), 1.0, 1e-12) << axes;
    expect_monte_carlo(c, m, 300000, 13, axes);
    PointCloud moved = c;
    const Vec3 shift(0.37, 0.21, 0.13);
    for (auto& x : moved.positions) {
      for (int k = 0; k < dim; ++k)
        if (c.domain.periodic[static_cast<std::size_t>(k)]) x[k] += shift[k];
      x = moved.domain.wrap(x);
    }
    const auto mm = voronoi_cell_measures(moved);
    for (std::size_t i = 0; i < m.size(); ++i) EXPECT_NEAR(mm[i], m[i], 1e-12) << axes << " particle " << i;
  }
  // A cloud that carries its images (periodic_stencil's extended clouds), and a part of one (a
  // rank's particles): the cells of their own points, exact where every point within twice a
  // cell's reach is there — the originals and the images near the box here.
  for (const auto& [dim, n] : {std::pair{2, 10}, std::pair{3, 7}}) {
    PointCloud c = perturbed_cloud(dim, n, 7);
    c.domain.set_periodic("all");
    const auto m = voronoi_cell_measures(c);
    const PeriodicImages images = periodic_images(c, 0.45);
    ASSERT_GT(images.cloud.size(), c.size());
    for (bool whole : {true, false}) {
      const auto mi = voronoi_cell_measures(images.cloud, whole);
      Index checked = 0;
      for (Index i = 0; i < images.cloud.size(); ++i) {
        const Vec3& x = images.cloud.positions[static_cast<std::size_t>(i)];
        Real outside = 0;  // how far beyond the box
        for (int k = 0; k < dim; ++k) outside = std::max({outside, -x[k], x[k] - 1});
        if (outside > 0.02) continue;
        EXPECT_NEAR(mi[static_cast<std::size_t>(i)], m[static_cast<std::size_t>(images.image_of[static_cast<std::size_t>(i)])], 1e-12)
            << dim << "D particle " << i;
        ++checked;
      }
      EXPECT_GT(checked, c.size()) << dim << "D";  // the originals and some images
    }
    // The originals alone as a part (not whole): cut at the faces, no longer the periodic cells.
    const auto part = voronoi_cell_measures(c, false);
    EXPECT_NEAR(sum(part), 1.0, 1e-12);
  }
  // 1D, and a periodic lattice: every cell one spacing (squared, cubed).
  for (int dim = 1; dim <= 3; ++dim) {
    PointCloud c = cell_centred_lattice(Domain::unit_box(dim), 5, false);
    c.domain.set_periodic("all");
    for (Real v : voronoi_cell_measures(c)) EXPECT_NEAR(v, std::pow(0.2, dim), 1e-14) << dim << "D";
  }
  PointCloud line = perturbed_cloud(1, 9, 2);
  line.domain.set_periodic("x");
  EXPECT_NEAR(sum(voronoi_cell_measures(line)), 1.0, 1e-14);
}
