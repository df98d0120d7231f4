#include <cmath>
#include <numbers>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>

namespace vrsph {

namespace {
// The assembled system per stencil entry: triplets while assembling (16 B), the CSC
// matrix (12 B) and the ILUT preconditioner and solver work space. Calibrated so that
// the whole estimate meets the measured peak resident memory of qw-ex5, VRSPH,
// BiCGSTAB + ILUT: 2D n = 1000 (3.17 GiB) and 3D n = 60 (2.72 GiB), both within 2 %.
// Direct solvers add their fill-in, which solve() checks separately.
constexpr double assembled_bytes_per_entry = 74;
// Work arrays of the stencil builders per neighbour pair (VRSPH's reconstructed
// volumes, kernel gradients): calibrated on the operator study, VRSPH Laplacian,
// perturbed, n = 2000 with ghosts (4.5 GiB measured, 4.6 GiB estimated).
constexpr double builder_bytes_per_entry = 16;
}  // namespace

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
                              + k * builder_bytes_per_entry
                              + (assembled ? k * assembled_bytes_per_entry : 0);
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
