// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Compact high-order rows (VRSPH option rhs=compact, beyond [QW]; docs/methods.md): a
// generalisation of Collatz's Mehrstellen scheme to particles. Row i is
//   Σ_j w_ij (u_j - u_i) = Σ_k μ_ik f_k,   w >= 0, μ >= 0, Σ_k μ_ik = 1,
// with w and μ found together (one NNLS or linear program per particle) so that the row is exact for every
// polynomial p of degree <= `degree` with f = L p = a Δp + ∇a·∇p at the stencil's particles.
// The left-hand side keeps VRSPH's M-matrix sign structure; the right-hand side becomes a
// positive average of f. Exact for degree 4: truncation O(h^3), against O(h^2) for the
// point right-hand side f_i (on a lattice the tie rule of the NNLS keeps the rows symmetric and
// the fifth moments cancel too: measured order 4.0 there). Where degree 4 admits no w, μ >= 0
// (next to a wall, or at a void of a disordered cloud) degree 3 is tried (O(h^2), still
// positive) and, with CompactRowOptions::signed_average, degree 4 with w >= 0 and a signed μ
// (the left-hand side, and with it the M-matrix, unchanged); rows with neither are left to the
// caller (VRSPH falls back on its own row with μ = δ_ik).
#include <span>
#include <vrsph/methods/method.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

struct CompactRows {
  std::vector<char> ok;         ///< per particle: 1 = a compact row was found
  std::vector<char> degree;     ///< per particle: the polynomial degree its row is exact for (0: none)
  std::vector<Real> mu_self;    ///< per particle: μ_ii
  std::vector<Real> residual;   ///< per particle: ||A x - b|| / ||b|| of the local system
  std::vector<Real> wall_flux;  ///< wall rows: c_i >= 0 of Σ w (u_j - u_i) = Σ μ f - c_i q_i; else empty
  std::vector<char> signed_average;  ///< per particle: 1 = its μ has negative entries (signed_average)
  /// The rows that found their positive row of the top degree on the wider support
  /// (CompactRowOptions::wide_support; with wide_lower_degrees also their row of a lower degree
  /// or signed average there), sorted by row: beyond the neighbour list, so not in the
  /// target's pattern; each with its diagonal (value 0, right-hand-side weight μ_ii). The
  /// caller puts them in place (replace_rows). Their other outputs above are filled as for
  /// any row.
  std::vector<RowReplacement> wide;
  Index wide_attempted = 0;  ///< rows that tried the wider support
};

/// Compact balance rows at wall particles (with flux=balance): one more unknown c_i >= 0 and
/// the row exact on p for Σ_j w_ij (p_j - p_i) + c_i (a n·∇p)_i = Σ_k μ_ik (L p)(x_k), so that
/// a Neumann condition a ∂u/∂n = q enters as -c_i q_i on the right-hand side.
struct CompactWalls {
  std::span<const char> rows;      ///< per particle: 1 = a wall row (empty: none)
  std::span<const Vec3> conormal;  ///< per particle: a_i n_i (the flux q = conormal·∇u)
};

struct CompactRowOptions {
  int degree = 4;      ///< the degree each row tries first
  int min_degree = 3;  ///< the lowest degree a row may fall to (>= 3)
  Real tolerance = 1e-8;  ///< relative residual above which a degree is not met
  /// In (0, 1]: each row first tries, at `degree`, only the neighbours within this fraction of
  /// its support radius (the most compact positive row; the others get weight 0), and takes
  /// the whole support where they admit none (1: the whole support only).
  Real inner_support = 1;
  /// A row whose degree d admits no w, μ >= 0 also tries d with w >= 0 and a signed μ (its
  /// negative part penalised) and keeps whichever of that row and the positive row of degree
  /// d - 1 has the smaller estimated truncation error (see wave_number). Off: the positive
  /// rows alone, as before this option.
  bool signed_average = false;
  /// The wave number k of the estimate that compares the two (the row's error on u taken as
  /// (k h)^m Σ_|α|=m |T_α| / α! at the first degree m it misses, T_α its residual on the
  /// monomial e^α): 0 means π / Discretisation::length_unit() (the whole cloud's largest side,
  /// on every rank), the smoothest mode the box holds.
  Real wave_number = 0;
  /// A row whose neighbours admit no positive row of `degree` (it fell to a lower degree, a
  /// signed average, or none) tries again over the particles within this multiple of its
  /// support radius, found through its neighbours' lists (so a halo must hold that many
  /// supports: Method::reach_for), and takes that row where it exists (CompactRows::wide). 1: no second try. Such rows sit
  /// by the voids of a disordered cloud and by walls, a few per 10^5 particles, and their
  /// O(h^2) or signed rows set the max-norm error at fine resolution.
  Real wide_support = 1;
  /// Where the wider support admits no positive row of `degree` either, the lower degrees (and
  /// signed averages) are tried over the wider support before the row's own support. Off: over
  /// the own support only (the degree-4 rows' way). For degrees above 4 by the walls, where
  /// the own support is one-sided: there the wider support's degree 5 beats the own support's
  /// degree 4 (docs/methods.md, `compact_degree`).
  bool wide_lower_degrees = false;
  /// Which of a degree's positive rows (there are many: the moment conditions leave w, μ a
  /// polytope) a row takes: off, the one Lawson–Hanson's NNLS path ends at; on, the one whose
  /// bound on the next degree's truncation, Σ_|α|=d+1 |T_α| / α! ≤ Σ_k |column_k(e^α)| x_k / α!,
  /// is least (a linear program, DenseSimplex; where it fails, the NNLS row). On a disordered
  /// cloud that row is 2-4 times more accurate at fourth order (docs/methods.md).
  bool least_truncation = false;
};

/// rows: the particles to build (empty: every non-ghost particle). a, grad_a: the
/// coefficient and its gradient at every particle (nullptr: a = 1, ∇a = 0). Each row takes
/// the highest degree from `degree` down to `min_degree` that admits w, μ >= 0 (or, with
/// signed_average, a signed μ; see CompactRowOptions).
/// The weights go straight into `out`, a zero pattern of disc.neighbours
/// (make_stencil_pattern) whose rhs has nnz entries: w_ij into values[0] and μ_ij into rhs
/// at the neighbour slots of each row that takes the compact form; the diagonal slots and the
/// other rows are left untouched (μ_ii is CompactRows::mu_self). Writing in place spares a
/// copy of two arrays of one value per neighbour pair.
CompactRows compact_rows(const Discretisation& disc, std::span<const char> rows, const Field* a,
                         const Eigen::MatrixXd* grad_a, const CompactRowOptions& options, Stencil& out,
                         const CompactWalls& walls = {});

}  // namespace vrsph
