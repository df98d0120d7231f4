// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Exact solutions of the incompressible Navier–Stokes equations on periodic boxes, for the
// convergence studies of the projection method (docs/flow.md):
//  - 2D: the Taylor–Green vortex of the periodic unit square,
//      u = -U e^{bt} cos 2πx sin 2πy,  v = U e^{bt} sin 2πx cos 2πy,
//      p = -U²/4 e^{2bt} (cos 4πx + cos 4πy),  b = -8π²ν (ν = U/Re, unit length);
//  - 3D: the same vortex cannot stay three-dimensional and exact (the classic 3D Taylor–Green
//    vortex is an initial condition that transitions), so the 3D case is the Beltrami flow of
//    the periodic unit cube with wavenumber k = 2π,
//      u = U e^{bt} (sin kz + cos ky,  sin kx + cos kz,  sin ky + cos kx),  b = -k²ν,
//    curl u = k u, so (u·∇)u = ∇|u|²/2 and p = -|u|²/2 (+ a constant): an exact, genuinely 3D
//    solution with the same decay mechanism (the Arnold–Beltrami–Childress flow, A = B = C = U).
#include <vrsph/core/types.hpp>

namespace vrsph {

struct PeriodicVortex {
  int dim = 2;   ///< 2: Taylor–Green, 3: Beltrami
  Real U = 1;    ///< velocity scale
  Real Re = 100; ///< Reynolds number U L / ν with L = 1 (the period)
  Real nu() const { return U / Re; }
  Real decay_rate() const;  ///< b: the amplitude is e^{bt}
  Vec3 velocity(const Vec3& x, Real t) const;
  Real pressure(const Vec3& x, Real t) const;
  /// max over the box of |u| and of |p - mean p| at time t.
  Real max_speed(Real t) const;
  Real max_pressure(Real t) const;
};

}  // namespace vrsph
