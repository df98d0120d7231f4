// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Diagonal permeability fields K = diag(k_x, k_y[, k_z]) on a Cartesian cell grid over the
// unit square/cube: the heterogeneous media of [SPE] §5.3 (METHODS §5.3, R18).
//
// SPE10 itself is not available offline (R18), so two reproducible synthetic fields stand
// in for it, labelled as substitutes wherever they are reported:
// - log-normal: ln k = ln k_mean + σ Z, Z a unit-variance Gaussian field with Gaussian
//   covariance exp(-r²/ℓ²) (white noise convolved with a separable Gaussian);
// - channelised: meandering channels of permeability contrast·k_b in a background k_b
//   (the fluvial layers 36-85 of SPE10 are channelised like this).
// A user who has SPE10's spe_perm.dat (or any field in its layout) reads it with
// read_permeability. Cells are square (cubic): the grid is mapped onto [0,1]^d whatever
// the physical cell sizes of the file were (SPE10's are 20 x 10 x 2 ft).
#include <array>
#include <cstdint>
#include <string>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct PermeabilityField {
  int dim = 2;
  int n = 0;                   ///< cells per axis (the grid is n^dim over [0,1]^dim)
  /// n^dim x dim: row c = i + n (j + n l) is cell (i, j, l), column k is k_k there.
  Eigen::MatrixXd k;
  Index cells() const { return static_cast<Index>(k.rows()); }
  Index cell_index(int i, int j, int l = 0) const { return i + static_cast<Index>(n) * (j + static_cast<Index>(n) * l); }
  /// The cell containing x (points on faces belong to the adjacent cell inside).
  Index cell_of(const Vec3& x) const;
  /// max / min over all entries.
  Real contrast() const;
  /// Every direction equal in every cell (a scalar coefficient describes it exactly).
  bool isotropic() const;
};

/// Throws InputError: dimension not 1..3, n < 1, wrong array size, an entry that is NaN,
/// infinite or <= 0 (names the cell and direction).
void validate(const PermeabilityField& field);

struct LognormalFieldOptions {
  Real k_mean = 100;                ///< geometric mean (e^{E ln k}), e.g. in mD
  Real sigma_ln = 1.5;              ///< standard deviation of ln k
  Real correlation_length = 0.1;    ///< ℓ of exp(-r²/ℓ²), in units of the domain (0: white noise)
  Real kz_ratio = 1;                ///< k_z = kz_ratio · k_x in 3D (k_y = k_x always)
  std::uint64_t seed = 1;
};
/// Reproducible on every platform and thread count (counter-based random numbers).
PermeabilityField lognormal_permeability(int dim, int n, const LognormalFieldOptions& options = {});

struct ChannelFieldOptions {
  Real k_background = 1;
  Real contrast = 1e6;              ///< k_channel / k_background (>= 1)
  int channels = 0;                 ///< 0: 4 in 2D, 8 in 3D
  Real kz_ratio = 1;
  std::uint64_t seed = 1;
};
/// Channels: axes at a random angle within 45° of y (the flow direction of the [SPE]
/// test), sinusoidal meanders (amplitude 0.03-0.12, wavelength 0.3-0.8, width 0.04-0.10 of
/// the domain), in 3D also a random depth and thickness (0.08-0.2). A cell belongs to a
/// channel when its centre does.
PermeabilityField channel_permeability(int dim, int n, const ChannelFieldOptions& options = {});

/// The layout of a permeability file: whitespace-separated numbers (Fortran 'D' exponents
/// accepted), one block per direction — k_x for every cell, then k_y, then k_z — each with
/// the I index fastest, then J, then K (SPE10's spe_perm.dat: grid 60 x 220 x 85, three
/// blocks, 3 366 000 values). A file with one block is isotropic. The field is the
/// subset I, J, K (1-based, inclusive) of the file's grid: n x n (x n) cells, the K range
/// a single layer in 2D.
struct PermeabilityFileLayout {
  std::array<int, 3> grid{60, 220, 85};
  std::array<std::array<int, 2>, 3> subset{{{1, 60}, {1, 60}, {85, 85}}};
  int dim = 2;
};
/// Throws IoError (unreadable), InputError (a token that is not a number, a count that is
/// not 1, 2 or 3 blocks of the grid, a subset outside the grid or not square, entries that
/// are not finite and positive).
PermeabilityField read_permeability(const std::string& path, const PermeabilityFileLayout& layout = {});
/// Writes the field in the same layout (grid n x n x n or n x n x 1, dim blocks).
void write_permeability(const std::string& path, const PermeabilityField& field);

}  // namespace vrsph
