#pragma once
// [IM] Table 1 / Fig. 5 (METHODS §5.4): truncation errors of the generalized particle
// method's interpolant, gradient and Laplacian with the reference weights pi/grad/delta
// 1-3 on the perturbed lattices of cloud/im_cloud.hpp (Omega_H = (-0.1, 1.1)^d,
// eta ~ U(-1/4, 1/4)), v = sin(2 pi (x_1 + ... + x_d)), V_i = |Omega_H| / N, and
// h_N = 2.6 * 2^(5/m - 5) * dx^(1/m). Errors are relative max norms over particles in
// Omega = (0,1)^d: all of them, or a seeded random subset of `max_points` when there are
// more (stated per row). Order = log(e_prev / e) / log(h_prev / h) between levels, as
// [IM]; order_fit = the least-squares slope over up to four levels, less sensitive to the
// level-to-level scatter of a maximum over a random subset.
// Neighbours come from the lattice index window (the perturbation is below dx/2), so no
// search structure is built; particles are generated once per level and shared.
#include <functional>
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct ImTable1Options {
  int dim = 2;
  std::vector<std::string> weights{"pi1", "pi2", "pi3", "grad1", "grad2", "grad3", "delta1", "delta2", "delta3"};
  std::vector<int> m{1, 3, 5};
  std::vector<int> levels{5, 6, 7, 8};  ///< dx = 2^-level
  Index max_points = 10000;             ///< evaluation points per level (random subset above)
  std::uint64_t seed = 1;               ///< the particle perturbation and the subset
  std::function<void(const std::string&, double)> progress;  ///< (label, fraction done), once per (level, m)
};

struct ImTable1Row {
  std::string weight;
  int m = 0, level = 0;
  Real dx = 0, h = 0;
  Index particles = 0, evaluated = 0, in_omega = 0;
  Real neighbours_mean = 0;
  Real error_rel = 0;
  Real order = 0;  ///< from the previous level; NaN on the first level
  Real order_fit = 0;  ///< least-squares slope of log e against log h over this and up to 3 previous levels (NaN on the first)
  Real seconds = 0;
};

/// Throws ConfigError for an unknown weight, m < 1, a level outside 2..14, dim outside 1..3.
std::vector<ImTable1Row> im_table1(const ImTable1Options& options);

/// [IM]'s theoretical rate for a weight (pi/grad/delta, family k) and m: min(m-1, n+1) for
/// pi and grad, min(m-2, n+1) for delta, n = 1 for k = 1, 2 and n = 3 for k = 3; NaN for
/// m = 1 (no convergence promised, "N/A" in Table 1).
Real im_theoretical_order(const std::string& weight, int m);

}  // namespace vrsph
