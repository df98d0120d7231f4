#include <cmath>
#include <numbers>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>

namespace vrsph {

RunFootprint estimate_run_footprint(int dim, double particles, double h_over_dx, int components, bool assembled) {
  RunFootprint f;
  f.particles = particles;
  // Lattice points in a ball of radius h/dx: its volume (omega_d r^d).
  const double r = h_over_dx;
  const double ball = dim == 1 ? 2 * r : dim == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  f.neighbours_per_particle = std::max(1.0, ball);
  const double k = f.neighbours_per_particle + 1;  // + the diagonal
  const double comps = components;
  const double per_particle = 2 * sizeof(Vec3) + 1                                 // position, normal, tag
                              + k * (sizeof(Index) + sizeof(Real))                 // neighbour list with distances
                              + k * (sizeof(Index) + comps * sizeof(Real))         // stencil
                              + (assembled ? 2 * k * (sizeof(Index) + sizeof(Real)) : 0);  // matrix + preconditioner
  f.bytes = particles * per_particle;
  return f;
}

void check_run_footprint(const RunFootprint& f, const std::string& what) {
  check_memory_estimate(f.bytes,
                        detail::concat("the run at ", what, " (about ", static_cast<long long>(f.particles),
                                       " particles with ", static_cast<long long>(f.neighbours_per_particle),
                                       " neighbours each)"),
                        "reduce --n or --h-factor");
}

}  // namespace vrsph
