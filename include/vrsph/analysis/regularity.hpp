// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Regularity report of a particle set ([IM] §2, (5)–(7), Theorem 3; METHODS §3.8.4–3.8.5):
// the covering radius r_N, the Voronoi deviation d_N of the particle volumes, the order m
// of regularity that a support radius h gives this set (the largest m with
// h^m >= c0 (r_N + d_N), [IM](7) read for one set; lengths in the cloud's units, h < 1),
// and the truncation orders Theorem 3 then predicts for the [IM] weights:
// interpolant and gradient min(m-1, n+1), Laplacian min(m-2, n+1), with n = 1 for the
// weights pi/grad/delta 1 and 2 and n = 3 for pi3/grad3/delta3.
// Ghost particles (outside the domain) take no part in d_N.
#include <string>
#include <vector>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/voronoi_deviation.hpp>
#include <vrsph/methods/particle_volumes.hpp>

namespace vrsph {

struct RegularityOptions {
  ParticleVolumes volumes = ParticleVolumes::Uniform;
  Real h = 0;   ///< support radius; 0 = 3 dx
  Real c0 = 1;  ///< the constant of (7)
  VoronoiDeviationOptions deviation;
};

struct PredictedOrder {
  std::string op;  ///< interpolant | gradient | laplacian
  int n;           ///< Hypothesis-1 order of the weight
  Real order;      ///< Theorem 3's rate in h (negative: no convergence promised)
};

struct RegularityReport {
  CoveringRadius covering;
  VoronoiDeviation deviation;
  Index particles = 0;  ///< taking part in d_N (ghosts excluded)
  Real spacing = 0, h = 0, c0 = 1;
  Real order = 0;       ///< largest real m with h^m >= c0 (r_N + d_N); 0 when h >= 1
  std::vector<PredictedOrder> predicted;
};

RegularityReport regularity(const PointCloud& cloud, const RegularityOptions& options = {});

}  // namespace vrsph
