// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// [IM] Table 1 / Fig. 5 (METHODS §5.4): truncation errors of the generalized particle
// method's interpolant, gradient and Laplacian with the reference weights pi/grad/delta
// 1-3 on the perturbed lattices of cloud/im_cloud.hpp (Omega_H = (-0.1, 1.1)^d,
// eta ~ U(-1/4, 1/4)), v = sin(2 pi (x_1 + ... + x_d)), V_i = |Omega_H| / N (or, as a
// control, the lattice cells), and h_N = 2.6 * 2^(5/m - 5) * dx^(1/m). Errors are relative
// max norms over particles in Omega = (0,1)^d: all of them, or a seeded random subset of `max_points` when there are
// more (stated per row). Order = log(e_prev / e) / log(h_prev / h) between levels, as
// [IM]; order_fit = the least-squares slope over up to four levels, less sensitive to the
// level-to-level scatter of a maximum over a random subset.
// Each row also carries the error split of [IM]'s proof: volume_bias = V_i / dx^d - 1 of the
// particles around Omega (the lattice does not tile Omega_H, so |Omega_H| / N differs from
// dx^d by a level-dependent O(dx)), and error_integral = |1 - (1 + volume_bias) mu(|k| h)|,
// the error of the integral operator the sums approximate with that volume density
// (analysis/plane_wave_multiplier.hpp). The rest of error_rel is quadrature error.
// Neighbours come from the lattice index window (the perturbation is below dx/2), so no
// search structure is built; particles are generated once per level and shared.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

enum class ImVolumes {
  Uniform,  ///< V_i = |Omega_H| / N ([IM] 5.4)
  Cells,    ///< V_i = the particle's lattice cell, the outermost ones stretched to the boundary of
            ///< Omega_H: dx^d inside, still summing to |Omega_H| (the Voronoi volumes of the
            ///< unperturbed lattice); removes volume_bias
};

struct ImTable1Options {
  int dim = 2;
  std::vector<std::string> weights{"pi1", "pi2", "pi3", "grad1", "grad2", "grad3", "delta1", "delta2", "delta3"};
  std::vector<int> m{1, 3, 5};
  std::vector<int> levels{5, 6, 7, 8};  ///< dx = 2^-level
  Index max_points = 10000;             ///< evaluation points per level (random subset above)
  std::uint64_t seed = 1;               ///< the particle perturbation and the subset
  ImVolumes volumes = ImVolumes::Uniform;
  std::function<void(const std::string&, double)> progress;  ///< (label, fraction done), once per (level, m)
};

struct ImTable1Row {
  std::string weight;
  int m = 0, level = 0;
  Real dx = 0, h = 0;
  Index particles = 0, evaluated = 0, in_omega = 0;
  Real neighbours_mean = 0;
  Real error_rel = 0;
  Real volume_bias = 0;     ///< V_i / dx^d - 1 of the particles the evaluation points see
  Real error_integral = 0;  ///< |1 - (1 + volume_bias) mu(|k| h)|: the integral operator's part of error_rel
  Real order = 0;  ///< from the previous level; NaN on the first level
  Real order_fit = 0;  ///< least-squares slope of log e against log h over this and up to 3 previous levels (NaN on the first)
  Real seconds = 0;
};

/// "uniform" or "cells"; ConfigError naming the option otherwise.
ImVolumes parse_im_volumes(const std::string& name, const char* option);

/// Throws ConfigError for an unknown weight, m < 1, a level outside 2..14, dim outside 1..3.
std::vector<ImTable1Row> im_table1(const ImTable1Options& options);

/// [IM]'s theoretical rate for a weight (pi/grad/delta, family k) and m: min(m-1, n+1) for
/// pi and grad, min(m-2, n+1) for delta, n = 1 for k = 1, 2 and n = 3 for k = 3; NaN for
/// m = 1 (no convergence promised, "N/A" in Table 1).
Real im_theoretical_order(const std::string& weight, int m);

}  // namespace vrsph
