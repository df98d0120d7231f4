// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The approximate projection of ISPH/MPS, with one method's operators on the particles: a
// velocity w (N x d) is made discretely divergence-free by
//     L φ = D w,    u = w - G φ
// with the method's Laplacian L (its pressure Poisson rows), gradient G and divergence D = Σ_c G_c.
// "Approximate": L is the method's own Laplacian, not D G, so D u is not zero but the Laplacian's
// truncation error applied to φ (second order for VRSPH); on a periodic box the part of D w no
// gradient can remove (its mean, in the left null vector's weights) is returned as the shift.
//
// Walls (particles tagged Dirichlet: their velocity is prescribed) keep their velocity, and their
// pressure rows carry the Neumann condition ∂φ/∂n = n·(w - u_wall) = 0, the projection's
// boundary condition. Two forms (docs/flow.md, "Walls"):
//  - balance rows (VRSPH): the wall particle's own Laplacian row over its half support, with
//    a wall-flux unknown c_i ≥ 0 in its moment conditions: row·φ ≈ Δφ_i - c_i ∂φ/∂n_i (the
//    rows of VRSPH's Neumann boundary value problems, flux=balance). The matrix keeps the
//    M-matrix sign pattern, and the projection is stable: its spectral radius 1 + 2e-4 on the
//    cavity's clouds, where the gradient rows below gave 1.04–1.52 (a tangential mode of the
//    first fluid layer that grew until the viscosity held it, measured);
//  - gradient rows (every other method): n·G φ, with the flow's gradient;
//  - extrapolated rows (free surfaces; Adami, Hu & Adams, J. Comput. Phys. 231 (2012) 7057):
//    p_w = Σ_f ω_wf (p_f + a_w·(x_w - x_f)) over the water particles f of the wall's support
//    (under a free surface not the detached surface particles — droplets, films and jets
//    without water below their surface, whose p = 0 is the air's),
//    ω the kernel's Shepard weights: the water's pressure carried to the wall along the
//    acceleration the wall balances (∇p = a there). Exact for the hydrostatic pressure wherever
//    the wall sees water — above the surface it is the pressure's linear extension, at a column's
//    foot it holds the water up — and an M-matrix row. A wall without water in its support takes
//    p = 0 (the air's).
//
// Free surfaces (free_surface.hpp's particles): φ = 0 and p = 0 there (Dirichlet rows, the ISPH
// and MPS practice); the equation is then regular (no pin, no shift, no mean removed). The fluid
// rows next to the surface are the method's rows over their truncated supports (VRSPH: its
// moment conditions over what the support holds, docs/free_surface.md).
#include <algorithm>
#include <vrsph/flow/pressure_poisson.hpp>
#include <vrsph/moving/operators.hpp>

namespace vrsph {

/// The operators' Laplacian as a matrix (a copy): what PressurePoisson factorises.
/// ConfigError when they keep no Laplacian or it has right-hand-side weights (compact rows: a
/// projection needs the operator's value at each particle).
CsrMatrix laplacian_matrix(const Operators& ops);

/// The wall particles of a cloud (tag Dirichlet) and their outward unit normals (none on a
/// periodic box). InputError for a wall particle without a unit normal, ConfigError for
/// Neumann or Ghost particles (a flow has no use for them).
struct Walls {
  std::vector<Index> index;
  std::vector<Vec3> normal;
  std::vector<char> is_wall;  ///< per particle (empty when there are no walls)
  bool empty() const { return index.empty(); }
};
Walls walls_of(const PointCloud& cloud);

/// The pressure equation's matrix over every particle: the Laplacian's rows at fluid particles
/// and the walls' rows (every row annihilates constants, as PressurePoisson requires).
struct PressureEquation {
  CsrMatrix matrix;
  Walls walls;
  /// Balance rows: c_i of each particle's row (0 at fluid particles); empty: the walls take
  /// gradient rows n·G.
  std::vector<Real> wall_flux;
  /// Per particle, 1 on a free surface (an identity row: p = 0); empty: no free surface.
  std::vector<char> surface;
  /// Extrapolated wall rows: per particle, s Σ_f ω_wf (x_w - x_f) at walls, s the rows' scale
  /// (0 elsewhere; empty: balance or gradient rows). The row's right-hand side is a_w · this.
  std::vector<Vec3> wall_offset;
  bool has_surface() const { return std::find(surface.begin(), surface.end(), 1) != surface.end(); }
};
/// Balance rows where the method has them (a "flux" option the user left unset or set to
/// balance; its "rhs" then point), else gradient rows. Throws as the method's build.
PressureEquation pressure_equation(const Operators& ops, const Walls& walls);
/// Extrapolated rows at the walls (Adami, Hu & Adams 2012: p_w = Σ_f W_wf (p_f + a_w·(x_w - x_f))
/// / Σ_f W_wf over the fluid in the support; each row times the fluid rows' mean |diagonal|):
/// the form of free-surface and Lagrangian flows.
/// `surface`: per particle, 1 on the free surface (identity rows: p = 0; the walls extrapolate
/// from the water and from the surface particles that have a neighbour in it, and walls without
/// either in their support take p = 0 too, the air's); empty: no free surface (a closed box: walls without water
/// walls take the mean of their neighbours, and the equation is singular like the balance
/// rows'). InputError for a `surface` of another size; GeometryError for a wall without neighbours.
PressureEquation extrapolated_pressure_equation(const Operators& ops, const Walls& walls, const std::vector<char>& surface);
/// Its right-hand side for a pressure whose gradient balances the acceleration a (N x d),
/// ∇²p = ∇·a inside, ∂p/∂n = n·a at walls and p = 0 on a free surface: D a at fluid particles;
/// at walls n·a (gradient rows), (D a)_i - c_i n·a_i (balance rows) or a_i·offset_i
/// (extrapolated rows); 0 at the surface and at dry walls.
Field pressure_rhs(const Operators& ops, const PressureEquation& eq, const Eigen::MatrixXd& a);
/// The pressure equation, factorised. On a periodic box and with balance rows its defect is
/// spread evenly (their left null vector is positive: quadrature weights); with gradient rows
/// along the left null vector, pinned at the first fluid particle (pressure_poisson.hpp: one
/// more factorisation, of the transpose, at set-up). `matrix`: the equation's (moved in:
/// PressurePoisson pins it in place); `wall_flux`: PressureEquation's.
/// With a free surface (`has_surface`) the equation is regular: PressurePoisson::regular.
/// `previous`: the equation of the previous positions; where it is a factorisation of the same
/// kind, the new one is solved nearby (PressurePoisson::nearby: no factorisation while the old
/// one preconditions within its iteration cap). Gradient rows at walls always factorise (their
/// left null vector needs the transpose's factorisation). `extrapolated`: the walls' rows are
/// extrapolated_pressure_equation's, without a free surface: the defect is spread evenly over
/// the fluid (the wall rows eliminated leave a Laplacian with a positive left null vector).
PressurePoisson pressure_poisson(CsrMatrix matrix, const Walls& walls, const std::vector<Real>& wall_flux,
                                 const SolverOptions& options, bool has_surface = false,
                                 const PressurePoisson* previous = nullptr, bool extrapolated = false);

struct Projected {
  Eigen::MatrixXd u;  ///< w - G φ
  Field phi;          ///< the potential removed (zero mean)
  Real shift = 0;     ///< PressurePoisson::Result::shift
  SolveReport report;
};

/// w projected with the operators' L (factorised in `ppe`: the pressure equation `eq`), G and D;
/// wall particles keep w (whose normal component must be the wall's). `phi_guess`: an initial
/// guess for an iterative solver (empty: none). InputError for a w of another shape.
Projected project(const Operators& ops, const PressurePoisson& ppe, const Eigen::MatrixXd& w, const Field& phi_guess = {},
                  const PressureEquation* eq = nullptr);

/// (u · G) u: the advection of u (N x d) by itself with the operators' gradient, N x d.
Eigen::MatrixXd advection(const Operators& ops, const Eigen::MatrixXd& u);

}  // namespace vrsph
