// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How a geometry (2D polygon, 3D closed surface) is filled with particles.
#include <cstdint>
#include <vrsph/core/types.hpp>

namespace vrsph {

enum class FillPattern {
  Lattice,    ///< interior particles on the axis-aligned lattice of the spacing (perturbed by delta)
  BlueNoise,  ///< interior particles as a Poisson-disk set grown from the boundary particles (no lattice alignment)
};

struct GeometryFill {
  Real spacing = 0;  ///< particle spacing (> 0)
  Real delta = 0;    ///< lattice perturbation amplitude in units of spacing, [0, 0.5); lattice pattern only
  std::uint64_t seed = 1;
  FillPattern pattern = FillPattern::Lattice;
  /// Lattice fills can be made in parts (one per MPI rank): part p of `parts` holds a range
  /// of the interior lattice's layers along the last axis, and part 0 also the boundary
  /// particles; the parts in order are the whole cloud's numbering (boundary first, then the
  /// lattice layer by layer). Blue noise grows from the boundary: whole clouds only.
  int part = 0, parts = 1;
};

/// Poisson-disk exclusion radius, as a fraction of the spacing, that gives about one particle
/// per spacing^d on average (measured: tests/unit/cloud/test_blue_noise.cpp).
Real blue_noise_radius_factor(int dim);

}  // namespace vrsph
