// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete moment (regularity) conditions of [QW] (eqs. (3.7), (3.16), (4.1)–(4.3); METHODS §3.2) as the rows of VRSPH's NNLS system.
//
// For centre i and neighbour j: A_{(beta,alpha), j} = x_ji^alpha d_beta W_ij, where
// d_beta W_ij = (grad_i W_ij)_beta = 1/2 Y_ij (x_ji)_beta, and b_{(beta,alpha)} = 1 if
// alpha = e_beta, else 0. Rows: beta = 1..d (outer) x alpha (inner) ordered 0, e_1..e_d,
// then the degree-2 monomials in lexicographic order ((2,0),(1,1),(0,2) in 2D).
// Laplace/Morris version (4.2): |alpha| <= 2 -> 3 / 12 / 30 rows in 1D / 2D / 3D.
// Gradient version (4.1): 1 <= |alpha| <= 2 -> 2 / 10 / 27 rows.
// Rows are unscaled and duplicates are kept (METHODS P6): scaling changes the minimiser.
#include <array>
#include <span>
#include <vrsph/core/types.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>

namespace vrsph {

/// WallLaplace: the Laplace rows with |alpha| <= 1 only (first and second moments, 2 / 6 / 12
/// rows), the set a balance row at a wall particle can meet with v >= 0 from one side: there
/// every x_ji points inwards, so the odd third moments cannot vanish (beyond [QW]; docs/methods.md).
enum class MomentConditions { Gradient, Laplace, WallLaplace };

/// Multi-indices alpha in the row order above (inner loop).
const std::vector<std::array<int, 3>>& moment_exponents(MomentConditions c, int dim);
/// Rows of the literal system: 3/12/30 (Laplace) or 2/10/27 (gradient).
int moment_rows(MomentConditions c, int dim);

/// Row layout of the system handed to NNLS.
///  Full:   the literal rows above, duplicates included.
///  Merged: every row equals (Y/2) x_ji^gamma with gamma = alpha + e_beta, so rows with the
///          same gamma are identical (x y appears for (beta=x, alpha=y) and (beta=y, alpha=x)).
///          Each set of c identical rows becomes one row scaled by sqrt(c): the NNLS objective
///          sum_r (A_r v - b_r)^2 is *unchanged*, so is its minimiser, while the system
///          shrinks to 3/9/19 rows (Laplace) or 2/7/16 (gradient). Default.
enum class MomentRows { Merged, Full };
int moment_rows(MomentConditions c, int dim, MomentRows layout);

/// Right-hand side of the Laplace system for an anisotropic target (beyond [QW]): with
/// w_j = v_j Y_ij the weights satisfy Σ_j w_j x_ji = first and Σ_j w_j x_ji x_jiᵀ =
/// 2 diag(second), third moments 0, so Σ_j w_j (u_j - u_i) ≈ first·∇u + Σ_k second_k ∂_kk u:
/// div(M grad u) for a diagonal M with second = (m_k) and first = (∂_k m_k). The default
/// target (0, 1) is the Laplacian's b of build_moment_system.
struct MomentTarget {
  Vec3 first = Vec3::Zero();
  Vec3 second = Vec3::Ones();
};
/// Overwrites b (rows of the given layout) with the target's right-hand side (Laplace or
/// WallLaplace).
void moment_targets(MomentConditions c, int dim, MomentRows layout, const MomentTarget& target, Real* b);
/// Row of the system (Laplace or WallLaplace, given layout) that holds the first moment
/// Σ v (Y/2) (x_ji)_k: where a balance row's wall-flux column enters.
int first_moment_row(MomentConditions c, int dim, MomentRows layout, int k);

/// Column scales (r_min / r_j)^2 for the neighbours at the given distances: multiplying the
/// moment columns by them (and the volumes found back by them) leaves the feasible set as it
/// is while NNLS's path, which admits the column with the largest multiplier, prefers the
/// nearest neighbours (VRSPH prefer=near, balance and compact rows; the power 2 helps, 8 broke
/// perturbed rows, docs/methods.md).
void nearest_first_scales(std::span<const Real> distances, std::vector<Real>& scale);
/// Fills the rows x n matrix A (column j for neighbour j; column-major, or row-major as the
/// NNLS solver works on it) and b (rows). xji[j] = x_j - x_i, half_y[j] = Y_ij / 2 =
/// -W'(r_ij)/r_ij >= 0.
void build_moment_system(MomentConditions c, int dim, const Vec3* xji, const Real* half_y, int n, Real* A, Real* b,
                         MomentRows layout = MomentRows::Full, MatrixOrder order = MatrixOrder::ColumnMajor);

}  // namespace vrsph
