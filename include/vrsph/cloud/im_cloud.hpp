// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The particle sets of [IM] §5.4 (METHODS §5.4): the lattice points i dx with i dx in
// Omega_H = (-H, 1+H)^d, each coordinate moved by eta dx with eta ~ U(-delta, delta)
// (counter-based random numbers: the same set for any thread count or order). No
// boundary particles; the domain is Omega_H; every particle is Interior. For dx = 2^-5,
// H = 0.1 in 2D this gives N = 39^2 = 1521 as in [IM] Fig. 4.
#include <cstdint>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct ImCloudSpec {
  int dim = 2;
  Real dx = 1.0 / 32;
  Real margin = 0.1;   ///< H
  Real delta = 0.25;   ///< eta ~ U(-delta, delta)
  std::uint64_t seed = 1;
};

/// Throws ConfigError for dim outside 1..3, dx <= 0, margin < 0, delta outside [0, 0.5),
/// or more than 5e8 particles.
PointCloud im_cloud(const ImCloudSpec& spec);

/// The indices i with i dx in (-H, 1+H): [first, last].
void im_lattice_range(Real dx, Real margin, long long& first, long long& last);

}  // namespace vrsph
