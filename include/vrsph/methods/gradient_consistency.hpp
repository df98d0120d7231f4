// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Raising a first-derivative stencil to exactness on cubic polynomials (our own, beyond the
// papers; docs/periodic.md "Vector operators").
//
// Why: a gradient row that is exact on quadratics (VRSPH's volumes, FPM's quadratic fit) errs
// by Σ_j g_ij (x_j - x_i)^α D^α u / α! over |α| = 3, an O(h^2) term whose constant is the row's
// fourth moment, different at every particle of a disordered cloud. Its largest value over N
// particles grows with N (heavy tails: a particle with a near-empty side), so the max-norm
// order of a divergence or a curl on 10^3 ... 10^5 random particles fits 1.8 while the l2
// order is 2.0. VRSPH cannot remove the term with its own volumes: for α = 3 e_β the moment
// Σ v_j (W'/r) (x_j - x_i)_β^4 has one sign, so no non-negative volumes make it vanish.
//
// What: each row's weights g_ik (one vector per neighbour) get the smallest change δ_ik in the
// kernel-weighted norm Σ_k |δ_ik|^2 / W(r_ik) that makes the row exact on every monomial of
// degree 1 ... 3 — the moving-least-squares correction of the given row:
//   δ_ik = W(r_ik) Σ_a P_ak y_a,  (P Ω P^T) y = b - P g,  P_ak = ((x_k - x_i) / h)^α_a,
// with b the exact derivatives of the monomials at x_i, and the diagonal kept at -Σ_k (the row
// stays exact on constants). The change is concentrated on the near neighbours (W) and is
// O(|g|) in size; the error of the raised row is O(h^3). A row whose cubic system is singular
// or worse conditioned than max_condition (after symmetric equilibration) — too few or
// one-sided neighbours, a corner — keeps its weights as they were.
#include <vrsph/methods/method.hpp>

namespace vrsph {

struct GradientConsistencyReport {
  Index raised = 0;  ///< rows now exact on cubics
  /// Requested rows left as they were (fewer neighbours inside the support than monomials, or a
  /// cubic system singular or ill-conditioned), ascending.
  std::vector<Index> kept;
};

/// The rows of `s` (Gradient, Dx, Dy or Dz in difference form on the neighbour-list pattern of
/// disc.neighbours: make_stencil_pattern's) that `req` asks for, raised to exactness on cubics.
/// Rows flagged in s.local_failure are left alone. Periodic pair lists are read through
/// Discretisation::neighbour_position.
/// max_condition: every row of the perturbed, periodic and walled clouds of the tests has an
/// equilibrated condition number below 1e3; the lid-driven cavity's corner and wall rows exceed
/// 1e4, and raised there (threshold 1e8) they made the flow blow up in its first step.
GradientConsistencyReport raise_to_cubic_exactness(const Discretisation& disc, const StencilRequest& req, Stencil& s,
                                                   Real max_condition = 1e4);

}  // namespace vrsph
