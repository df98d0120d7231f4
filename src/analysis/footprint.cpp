// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/analysis/footprint.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>

namespace vrsph {

namespace {
// The assembled system per stencil entry, by solver. The BVP solve releases the
// neighbour list after the stencils and the stencils after assembly, so the builders'
// work arrays and the assembled system are never held together: the estimate takes the
// larger of the two (plus, conservatively, the list and stencil).
// - PETSc + BoomerAMG: compressed rows, their row-scaled values, hypre's copy and the AMG
//   hierarchy; calibrated on qw-ex5 2D n = 1000 VRSPH (1.32 KB per particle measured,
//   1.6 KB estimated); SPH keeps all ~29 entries per row and stays below it.
// - BiCGSTAB + ILUT: calibrated (with the earlier assembly) on 2D n = 1000 (3.17 GiB)
//   and 3D n = 60 (2.72 GiB), within 2 %.
// - direct: the matrix and its column copy; the LU fill-in is checked by solve().
double assembled_bytes_per_entry(SolverType solver) {
  switch (solver) {
    case SolverType::Petsc: return 30;
    case SolverType::BiCGSTAB: return 90;
    default: return 30;
  }
}
// Work arrays of the stencil builders per neighbour pair (VRSPH's reconstructed
// volumes, kernel gradients): calibrated on the operator study, VRSPH Laplacian,
// perturbed, n = 2000 with ghosts (4.5 GiB measured, 4.6 GiB estimated).
constexpr double builder_bytes_per_entry = 16;
}  // namespace

RunFootprint estimate_run_footprint(int dim, double particles, double h_over_dx, int components, bool assembled,
                                    SolverType solver) {
  RunFootprint f;
  f.particles = particles;
  // Lattice points in a ball of radius h/dx: its volume (omega_d r^d).
  const double r = h_over_dx;
  const double ball = dim == 1 ? 2 * r : dim == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  f.neighbours_per_particle = std::max(1.0, ball);
  const double k = f.neighbours_per_particle + 1;  // + the diagonal
  const double comps = components;
  const SolverType resolved =
      solver == SolverType::Auto ? resolve_auto(static_cast<Index>(std::min(particles, 2e9)), dim) : solver;
  const double per_particle = 2 * sizeof(Vec3) + 1                                 // position, normal, tag
                              + k * (sizeof(Index) + sizeof(Real))                 // neighbour list with distances
                              + k * (sizeof(Index) + comps * sizeof(Real))         // stencil
                              + std::max(k * builder_bytes_per_entry,
                                         assembled ? k * assembled_bytes_per_entry(resolved) : 0.0);
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
