// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Blue-noise (Poisson-disk) point sets: no two points closer than a radius r, and no gap
// much wider than 2r. Used to fill geometries when a lattice's alignment is unwanted
// (`vrsph cloud --geometry ... --family blue-noise`) and to spread particles over curved
// surfaces, where no lattice exists. Deterministic for a seed, on any thread count.
#include <cstdint>
#include <functional>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

/// Bridson's algorithm (SIGGRAPH sketches 2007) grown from the fixed points `seeds` (e.g. the
/// boundary particles, which therefore keep interior particles at least r away): each point
/// in turn (first in, first out) tries `attempts` candidates uniform in the shell [r, 2r]
/// around it; a candidate is kept when admissible(x) holds and no seed or kept point lies
/// closer than r. Only admissible points reachable from the seeds are produced. Returns the
/// new points (the seeds excluded). Throws ConfigError for r <= 0 or a dimension outside 1-3.
std::vector<Vec3> grow_blue_noise(int dim, Real r, const std::vector<Vec3>& seeds,
                                  const std::function<bool(const Vec3&)>& admissible, std::uint64_t seed,
                                  int attempts = 30);

/// Dart throwing over given candidates: visits them in an order drawn from `seed` and keeps
/// each one that has no kept point, and no point of `fixed`, closer than r. Returns the kept
/// candidates' indices in the order kept. With candidates dense enough (many per r^d) the
/// result is a maximal Poisson-disk set of the candidates' support.
std::vector<std::size_t> thin_to_blue_noise(const std::vector<Vec3>& candidates, Real r,
                                            const std::vector<Vec3>& fixed, std::uint64_t seed);

}  // namespace vrsph
