// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Voronoi deviation d_N of a particle set with volumes V_i ([IM](6), LP (63) with the
// erratum S5; METHODS §3.8.4): how far the volumes are from the clipped Voronoi cell
// measures |sigma_i|, in units of length. d_N = 0 iff V_i = |sigma_i|.
//
// LP (63) over the transport a_ij >= 0 (~ |sigma_i ∩ xi_j|): minimise q subject to
// sum_j a_ij = |sigma_i|, sum_j a_ji = V_i, q >= sum_j (a_ij + a_ji) |x_i - x_j| / |sigma_i|.
// Solved with COIN-OR Clp (see docs/methods.md for why Clp and not GLPK). Restrictions,
// each of which can only raise the minimum, so the result is then an upper bound:
//  * pairs farther apart than `radius` are left out (all pairs when radius covers the set);
//  * above `direct_limit` particles the set is cut into spatial blocks: the blocks'
//    imbalances sum_B (|sigma_i| - V_i) are moved between neighbouring blocks by a
//    potential flow on the block graph (each crossing pair carries the potential jump),
//    then each block solves its own LP (63) with those crossing flows fixed; if a block
//    LP is then infeasible, one LP over the whole set is solved instead (block_fallback).
// The reported value is recomputed from the transport found, whose row and column sums
// are checked; an LP that fails or hits its time limit is an error, never a number.
#include <span>
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

/// How d_N is bounded: LP (63) (the minimum over the decompositions within the pair radius;
/// by spatial blocks above direct_limit), or the potential flow: one decomposition from a
/// graph-Laplacian solve over the pairs, an upper bound that is not minimised but costs one
/// sparse factorisation (10^5 particles in about a second). Auto: the LP up to flow_above
/// particles, the flow above.
enum class DeviationMethod { Auto, Lp, Flow };
/// "auto" | "lp" | "flow"; throws ConfigError otherwise.
DeviationMethod parse_deviation_method(const std::string& name);

struct VoronoiDeviationOptions {
  DeviationMethod method = DeviationMethod::Auto;
  Index flow_above = 20000;    ///< Auto: more particles than this use the potential flow
  Real radius = 0;             ///< pair radius rho; 0 = 2 dx (dx = the cloud's spacing)
  Index direct_limit = 3000;   ///< more particles: block decomposition
  Index block_particles = 500; ///< target particles per block
  Index fallback_limit = 12000; ///< blocks that fail fall back to one LP only up to this many particles
  bool normalise_volumes = false;  ///< scale V so that sum V = sum |sigma| (else a mismatch is an error, S9)
  Real max_seconds = 600;      ///< per LP
};

struct VoronoiDeviation {
  Real value = 0;               ///< d_N (or its upper bound)
  bool is_upper_bound = false;
  std::string method;           ///< "lp" | "lp-restricted" | "lp-blocks" | "potential-flow"
  Real radius = 0;              ///< rho used (the first feasible of rho, 1.5 rho, ...)
  Index worst = -1;             ///< particle attaining the maximum
  Index blocks = 1;
  bool block_fallback = false;  ///< blocks were tried, their crossing flows did not fit, one LP was solved
  Index variables = 0, constraints = 0;  ///< of the largest LP solved
  Real seconds = 0;
  Real volume_sum = 0, cell_sum = 0;     ///< before any normalisation
  bool volumes_normalised = false;
};

/// volumes and cells: one entry per particle of `cloud` (cells from voronoi_cell_measures).
/// Throws InputError on size mismatch, negative or non-finite entries, a particle with an
/// empty cell but positive volume (d_N infinite), or sum V != sum |sigma| beyond 1e-9
/// relative unless normalise_volumes; NumericalError when an LP fails.
VoronoiDeviation voronoi_deviation(const PointCloud& cloud, std::span<const Real> volumes, std::span<const Real> cells,
                                   const VoronoiDeviationOptions& options = {});

}  // namespace vrsph
