// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The steady boundary value problems of [SPE] §5 (METHODS
// §5.3) on the unit square: the Laplace equation with
//   spe-dirichlet  u = ψ1 on y = 0, ψ2 on x = 1, ψ3 on y = 1, ψ4 on x = 0 (series (96) as
//                  corrected in METHODS §5.3: the printed ψ3 term duplicates ψ2's, R10);
//                  corner particles carry the mean of their two sides;
//   spe-mixed      u = ψ1 on y = 0 and outward normal derivatives ψ2 (x = 1), ψ3 (y = 1),
//                  ψ4 (x = 0) (series (98) with sin, not sinh, in y, R11); Neumann–Neumann
//                  corners take (g1 + g2)/√2 along the normalised mean normal (METHODS §4).
// ψ = (150, 90, 150, 200) (METHODS R15: the paper gives them only for the mixed test).
// The series are summed with recurrences for sin(nθ) and the exponentials (sinh ratios in
// exponential form, §5.3), so 4000 (Dirichlet) and 2·10^4 (mixed) terms cost ~10 flops each.
#include <array>
#include <memory>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/problem/diffusion.hpp>

namespace vrsph {

struct SpeBoundaryData {
  std::array<Real, 4> psi{150, 90, 150, 200};  ///< ψ1 (y = 0), ψ2 (x = 1), ψ3 (y = 1), ψ4 (x = 0)
};

/// Exact solution (96) at a point of the open square (odd n up to 2 terms - 1; the sum stops
/// early once the terms are below 1e-17 of ψ).
Real spe_dirichlet_solution(const Vec3& x, const SpeBoundaryData& data, int terms = 4000);
/// Dirichlet data of spe-dirichlet: the side's ψ, the mean of both sides at a corner; the
/// series inside.
Real spe_dirichlet_boundary(const Vec3& x, const SpeBoundaryData& data);
/// Exact solution (98) of spe-mixed on the closed square (n = 1 .. terms).
Real spe_mixed_solution(const Vec3& x, const SpeBoundaryData& data, int terms = 20000);
/// Outward flux ∂u/∂n of spe-mixed at a Neumann particle on x = 0, x = 1 or y = 1 (corners:
/// (g1 + g2)/√2).
Real spe_mixed_flux(const Vec3& x, const SpeBoundaryData& data);

/// [SPE] §4.4 plate flow (84)–(89) with Re = 1 and Δw/L = 1: the start-up of a channel flow,
/// v(y, t) = ½(1 - y²) - (16/π³) Σ_n (-1)^n/(2n+1)³ cos((2n+1)πy/2) e^{-((2n+1)π/2)² t}.
Real spe_plate_velocity(Real y, Real t);
/// The plate-flow diffusion problem ∂v/∂t = ∇²v + 1 on [0, 2] x [-1, 1] (uniform lattice of
/// spacing dx; the walls y = ±1 and the inlet/outlet x = 0, 2 carry the analytic profile),
/// v = 0 at t = 0, exact solution v^a.
DiffusionProblem spe_plate_problem(Real dx);
/// [SPE] Table 1: log10 E^n at t = 1..10 for ν = 0.1, 0.2, 0.25, 0.26 (row t-1, column ν).
const std::array<std::array<Real, 4>, 10>& spe_plate_table1();

/// The two solutions (and the Dirichlet data) as ScalarFunctions for the studies.
std::unique_ptr<ScalarFunction> make_spe_function(const std::string& which, const SpeBoundaryData& data = {});

}  // namespace vrsph
