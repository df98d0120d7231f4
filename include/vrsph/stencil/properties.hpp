// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Structural properties of a stencil: row sums, sign structure, the M-matrix
// test behind the discrete maximum principle, and exactness on monomials.
#include <array>
#include <functional>
#include <span>
#include <string>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

/// sum_k values[c][k] over each row (0 for difference-form operators).
Field row_sums(const Stencil& s, int component = 0);

/// Result of testing -L (restricted to unknown rows/columns) for the M-matrix property
/// by weak chained diagonal dominance ([QW] Thm 5.1 / Cor 5.2, METHODS §3.2):
///  (1) Z-matrix: every off-diagonal entry of -L between unknowns is <= 0 (L_ij >= 0);
///  (2) every row of -L is weakly diagonally dominant: -L_ii >= sum_{j unknown} |L_ij|;
///  (3) from every unknown row a path of non-zero entries reaches a strictly dominant
///      row (typically one linked to a Dirichlet particle).
/// (1)+(2)+(3) make -L a non-singular M-matrix.
struct MMatrixReport {
  bool z_matrix = true;
  bool diagonally_dominant = true;
  bool chained = true;
  Index rows = 0;                 ///< unknown rows examined
  Index positive_offdiagonal = 0; ///< count of L_ij < -tol (violations of (1))
  Index non_dominant_rows = 0;    ///< violations of (2)
  std::vector<Index> unreachable; ///< unknown rows with no path to a strictly dominant row
  Index first_violation = -1;     ///< particle index of the first failing row
  bool is_m_matrix() const { return z_matrix && diagonally_dominant && chained; }
  std::string summary() const;
};
/// unknown[i] says whether particle i is an unknown (row and column kept).
/// tol is relative to the largest |L_ij| of each row.
MMatrixReport check_m_matrix(const Stencil& s, std::span<const char> unknown, Real tol = 1e-12);
/// Closes condition (3): given the edges i -> j (CSR over the particles: j in
/// targets[offsets[i] .. offsets[i+1])) and the strictly dominant rows, the rows that reach one.
using ChainClosure = std::function<std::vector<char>(std::span<const Index> offsets, std::span<const Index> targets,
                                                     std::vector<char> seeds)>;
/// The same test on one rank's part of a distributed matrix: only the rows with rows[i] = 1
/// are examined, `unknown` marks every unknown column (halo copies included), and `close`
/// follows the chains over the ranks (reach_over_ranks).
MMatrixReport check_m_matrix(const Stencil& s, std::span<const char> unknown, Real tol, std::span<const char> rows,
                             const ChainClosure& close);

/// The largest |eigenvalue| of component 0 restricted to the active rows and columns (active[i]
/// = 1; the other columns count as data), by `iterations` power iterations from a fixed
/// pseudo-random start: what an explicit step's Δt must stay below 2/ρ of. Not a bound: an
/// isolated eigenvalue (one dominant row) is found in a few steps, a cluster (a lattice's
/// checkerboard modes) is estimated from below by at most its width, and a strongly non-normal
/// matrix can be over-estimated. Deterministic for a given stencil and mask.
Real spectral_radius(const Stencil& s, std::span<const char> active, int iterations = 60);

/// The method's local problems (Stencil::residual, e.g. VRSPH's NNLS) over selected rows.
/// Relative residual = ||A v - b|| / sqrt(d) (|b| = sqrt(d)); a row is infeasible when it
/// exceeds `tolerance` or its local solve failed (then listed with residual +inf).
struct LocalResidualSummary {
  Real max_relative = 0;                    ///< over rows whose solve did not fail
  Index infeasible = 0;
  std::vector<std::pair<Real, Index>> worst; ///< up to max_listed (relative residual, particle), largest first
};
/// Empty summary for methods without local problems.
LocalResidualSummary summarise_local_residuals(const Stencil& s, std::span<const char> rows, Real tolerance,
                                               std::size_t max_listed = 10);

/// Residual of the stencil on the monomial (x - x_i)^alpha centred at each row
/// particle, made dimensionless by the row's support radius s_i:
///   max over rows of | sum_j L_ij (x_j - x_i)^alpha - exact_alpha | * s_i^(order - |alpha|),
/// where exact_alpha is the operator applied to the monomial at x_i (1 for d/dx_k of
/// x_k, 2 for the Laplacian of x_k^2, ...). Only for Value, Dx/Dy/Dz, Gradient and Hessian
/// (Euclidean norm over components) and Laplacian.
struct MonomialResidual {
  std::array<int, 3> exponent;
  Real max_residual;
};
std::vector<MonomialResidual> monomial_residuals(const Stencil& s, const PointCloud& cloud, std::span<const Real> row_scale,
                                                 int max_degree, std::span<const char> rows);

}  // namespace vrsph
