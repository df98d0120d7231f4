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
};

/// Poisson-disk exclusion radius, as a fraction of the spacing, that gives about one particle
/// per spacing^d on average (measured: tests/unit/cloud/test_blue_noise.cpp).
Real blue_noise_radius_factor(int dim);

}  // namespace vrsph
