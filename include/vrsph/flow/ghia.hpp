// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The lid-driven cavity's reference centre-line velocities of U. Ghia, K. N. Ghia and C. T. Shin,
// "High-Re solutions for incompressible flow using the Navier–Stokes equations and a multigrid
// method", J. Comput. Phys. 48 (1982) 387–411, Tables I (u on the vertical line x = 0.5) and II
// (v on the horizontal line y = 0.5), Re = 100 and 1000 (a 129 x 129 grid); docs/flow.md says
// where the values were checked.
//
// Beside them, at the same points, a converged solution of the same problem (the lid between
// the corners): Taylor–Hood P2–P1 finite elements on 128 x 128 crossed cells (296 195 unknowns),
// by scripts/cavity_reference.py (FEniCSx 0.5), within 1e-4 of the 64 x 64 solution. Ghia's
// table is itself 5.0e-3 (u) and 9.2e-3 (v) from it at Re = 100, 6.3e-3 and 1.85e-2 at
// Re = 1000: a deviation from Ghia below those is not a better solution.
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct GhiaProfiles {
  Real re = 0;
  std::vector<Real> y, u;  ///< u(0.5, y), y from 1 down to 0 (the table's order)
  std::vector<Real> x, v;  ///< v(x, 0.5), x from 1 down to 0
  std::vector<Real> u_converged, v_converged;  ///< the converged P2–P1 solution at y and x
};
/// Re = 100 or 1000; ConfigError for another Reynolds number (naming the two).
const GhiaProfiles& ghia_profiles(Real re);

}  // namespace vrsph
