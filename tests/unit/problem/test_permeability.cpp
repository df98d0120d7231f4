// SPDX-License-Identifier: BSD-3-Clause
// Permeability fields: the synthetic substitutes for SPE10 (statistics, reproducibility,
// contrast) and the spe_perm.dat reader (layout, subset, every malformed input).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/permeability.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("vrsph-test-" + std::to_string(::getpid()) + "-" + name)).string();
}
void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}
}  // namespace

TEST(Permeability, LognormalHasTheRequestedStatisticsAndCorrelation) {
  LognormalFieldOptions o;
  o.k_mean = 50;
  o.sigma_ln = 2;
  o.correlation_length = 0.03;  // ~6 cells at n = 200: many independent samples
  const PermeabilityField f = lognormal_permeability(2, 200, o);
  ASSERT_EQ(f.cells(), 40000);
  double mean = 0, var = 0;
  for (Index c = 0; c < f.cells(); ++c) mean += std::log(f.k(c, 0));
  mean /= static_cast<double>(f.cells());
  for (Index c = 0; c < f.cells(); ++c) var += std::pow(std::log(f.k(c, 0)) - mean, 2);
  var /= static_cast<double>(f.cells() - 1);
  EXPECT_NEAR(mean, std::log(50.0), 0.25);       // ± a few standard errors of ~ (200 ℓ)^-1 correlated samples
  EXPECT_NEAR(std::sqrt(var), 2.0, 0.3);
  // Correlation at lag ℓ along x is e^{-1} for exp(-r²/ℓ²) (lag 6 cells = 0.03).
  double cov = 0;
  Index count = 0;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i + 6 < 200; ++i, ++count)
      cov += (std::log(f.k(f.cell_index(i, j), 0)) - mean) * (std::log(f.k(f.cell_index(i + 6, j), 0)) - mean);
  EXPECT_NEAR(cov / static_cast<double>(count) / var, std::exp(-1.0), 0.12);
  EXPECT_TRUE(f.isotropic());
}

TEST(Permeability, GeneratedFieldsAreReproducibleAndDependOnTheSeed) {
  LognormalFieldOptions o;
  const auto a = lognormal_permeability(3, 12, o), b = lognormal_permeability(3, 12, o);
  EXPECT_EQ(a.k, b.k);
  o.seed = 2;
  EXPECT_NE(a.k, lognormal_permeability(3, 12, o).k);
  ChannelFieldOptions c;
  EXPECT_EQ(channel_permeability(2, 30, c).k, channel_permeability(2, 30, c).k);
  c.seed = 5;
  EXPECT_NE(channel_permeability(2, 30, {}).k, channel_permeability(2, 30, c).k);
}

TEST(Permeability, ChannelisedFieldHasTheContrastAndConnectedChannels) {
  for (int dim : {2, 3}) {
    ChannelFieldOptions o;
    o.kz_ratio = dim == 3 ? 0.1 : 1;
    const PermeabilityField f = channel_permeability(dim, 60, o);
    EXPECT_DOUBLE_EQ(f.k.col(0).maxCoeff() / f.k.col(0).minCoeff(), 1e6);
    const double fraction = static_cast<double>((f.k.col(0).array() > 1).count()) / static_cast<double>(f.cells());
    EXPECT_GT(fraction, dim == 2 ? 0.05 : 0.02) << dim << "D";
    EXPECT_LT(fraction, 0.6) << dim << "D";
    EXPECT_EQ(f.isotropic(), dim == 2);
    if (dim == 3) {
      EXPECT_DOUBLE_EQ(f.k(0, 2), 0.1 * f.k(0, 0));
    }
  }
}

TEST(Permeability, FileRoundTripAndSpe10Layout) {
  // A 4 x 5 x 3 grid with three blocks: value = 1000 block + 100 K + 10 J + I (1-based).
  const std::string path = temp_path("perm.dat");
  {
    std::ofstream out(path);
    for (int b = 0; b < 3; ++b)
      for (int l = 1; l <= 3; ++l)
        for (int j = 1; j <= 5; ++j)
          for (int i = 1; i <= 4; ++i) out << (b + 1) * 1000 + 100 * l + 10 * j + i << ((i + j) % 3 ? " " : "\n");
  }
  PermeabilityFileLayout L;
  L.grid = {4, 5, 3};
  L.subset = {{{2, 3}, {4, 5}, {3, 3}}};  // a 2 x 2 2D layer: I = 2..3, J = 4..5, K = 3
  const PermeabilityField f = read_permeability(path, L);
  ASSERT_EQ(f.n, 2);
  EXPECT_DOUBLE_EQ(f.k(f.cell_index(0, 0), 0), 1342);
  EXPECT_DOUBLE_EQ(f.k(f.cell_index(1, 1), 1), 2353);
  L.dim = 3;
  L.subset = {{{1, 3}, {2, 4}, {1, 3}}};
  const PermeabilityField g = read_permeability(path, L);
  EXPECT_DOUBLE_EQ(g.k(g.cell_index(2, 0, 1), 2), 3223);
  // Written and read back exactly (17 digits), as an n x n x n grid.
  const std::string copy = temp_path("copy.dat");
  write_permeability(copy, lognormal_permeability(3, 5));
  PermeabilityFileLayout C;
  C.grid = {5, 5, 5};
  C.subset = {{{1, 5}, {1, 5}, {1, 5}}};
  C.dim = 3;
  EXPECT_EQ(read_permeability(copy, C).k, lognormal_permeability(3, 5).k);
  // Fortran exponents and a single (isotropic) block.
  write_text(path, "1.0D+00 2.0d0\n3.0E0 4\n");
  PermeabilityFileLayout I;
  I.grid = {2, 2, 1};
  I.subset = {{{1, 2}, {1, 2}, {1, 1}}};
  const PermeabilityField iso = read_permeability(path, I);
  EXPECT_TRUE(iso.isotropic());
  EXPECT_DOUBLE_EQ(iso.k(3, 1), 4);
  std::filesystem::remove(path);
  std::filesystem::remove(copy);
}

TEST(Permeability, MalformedFilesAndSettingsAreNamed) {
  const std::string path = temp_path("bad.dat");
  PermeabilityFileLayout L;
  L.grid = {2, 2, 1};
  L.subset = {{{1, 2}, {1, 2}, {1, 1}}};
  const std::pair<const char*, const char*> malformed[] = {
      {"1 2 3\n", "has 3 values; the grid 2 x 2 x 1 needs 4"},
      {"1 2 3 4 5 6 7 -8\n", "k_y of cell (I, J, K) = (2, 2, 1) is -8"},
      {"1 2 nan 4\n", "is nan"},
      {"1 2 x3 4\n", "line 1: 'x3' is not a number"},
      {"1 2 3 4 0 1 1 1\n", "is 0"},
      {"", "has 0 values"}};
  for (const auto& [content, message] : malformed) {
    write_text(path, content);
    EXPECT_THROW_MSG(read_permeability(path, L), InputError, message);
  }
  write_text(path, "1 1 1 1 1 1 1 1\n");
  L.dim = 3;
  EXPECT_THROW_MSG(read_permeability(path, L), ConfigError, "must be square");
  L.dim = 2;
  L.subset = {{{1, 3}, {1, 3}, {1, 1}}};
  EXPECT_THROW_MSG(read_permeability(path, L), ConfigError, "is not a range inside 1:2");
  EXPECT_THROW_MSG(read_permeability(temp_path("missing.dat"), {}), IoError, "permeability file");
  std::filesystem::remove(path);
  EXPECT_THROW_MSG(lognormal_permeability(2, 0), ConfigError, "cells per axis");
  LognormalFieldOptions o;
  o.sigma_ln = std::nan("");
  EXPECT_THROW_MSG(lognormal_permeability(2, 10, o), ConfigError, "sigma");
  ChannelFieldOptions c;
  c.contrast = 0.5;
  EXPECT_THROW_MSG(channel_permeability(2, 10, c), ConfigError, "contrast");
  PermeabilityField f = lognormal_permeability(2, 4);
  f.k(5, 1) = std::numeric_limits<Real>::infinity();
  EXPECT_THROW_MSG(validate(f), InputError, "k_y of cell (I, J, K) = (2, 2, 1) is inf");
}
