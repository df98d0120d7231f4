// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Memory of one study run (cloud, neighbour list, stencil, assembled system), estimated
// from the lattice size and the support radius *before* the cloud is generated, so an
// oversized refinement level is refused at once instead of after gigabytes of cloud
// and minutes of neighbour search. Each stage checks its own exact size again later.
#include <string>
#include <vrsph/core/types.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

struct RunFootprint {
  double particles = 0;               ///< including ghosts
  double neighbours_per_particle = 0; ///< lattice points in the support ball
  double bytes = 0;
};

/// particles: expected particle count; h_over_dx: support radius in spacings;
/// components: values per stencil entry (1, or d for a gradient); assembled: a linear
/// system and a preconditioner/factorisation of the stencil's pattern follow, by
/// `solver` (auto: what it would pick for this size; direct solvers' fill-in is checked
/// separately before the factorisation).
RunFootprint estimate_run_footprint(int dim, double particles, double h_over_dx, int components, bool assembled,
                                    SolverType solver = SolverType::Auto);

/// Throws ResourceError (via check_memory_estimate) naming the level `what` (e.g. "n = 2000").
void check_run_footprint(const RunFootprint& footprint, const std::string& what);

}  // namespace vrsph
