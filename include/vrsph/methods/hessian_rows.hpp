// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Rows for the second derivatives ∂_b ∂_c u (OperatorKind::Hessian), exact on quartic polynomials,
// for every method (our own, beyond the papers; docs/periodic.md "Vector operators").
//
// Why: the gradient of a divergence composed from a method's gradient rows, G_b (Σ_c G_c U_c),
// differentiates the first gradient's error, which is not smooth from one particle to the next
// on a disordered cloud: even with rows exact on cubics it fits 1.57 (VRSPH) / 1.86 (FPM) in the
// max norm. A row for ∂_b ∂_c itself, exact on every polynomial of degree ≤ 4, errs by
// Σ_k H_ik O(|x_k - x_i|^5) = O(h³) at every particle: third order in the max norm.
//
// What: the moving-least-squares derivative on the method's neighbours and kernel — each row's
// weights the smallest in Σ_k |H_ik|² / W(r_ik) that are exact on the monomials of degree
// 1 ... 4 (methods/cubic_rows.hpp), the diagonal -Σ_k (exact on constants): O(h³) on disordered
// clouds, where exactness on cubics alone left a constant 55 times larger (docs/periodic.md). The rows depend on
// the neighbour list, the support radii and the kernel only; no method's volumes enter (VRSPH's
// NNLS keeps about ten neighbours a row, too few for a well-conditioned cubic fit in 2D).
#include <string>
#include <vrsph/methods/method.hpp>

namespace vrsph {

/// Hessian rows on the pattern of disc.neighbours (make_stencil_pattern's), for the rows `req`
/// asks for (req.kind is not read), exact on the polynomials of degree ≤ `degree` (4: third order
/// on disordered clouds; 3: second; 2: first). Periodic pair lists are read through
/// Discretisation::neighbour_position. A row with fewer neighbours inside its support than the
/// monomials of degree 1 ... `degree` (2D: 14, 9, 5; 3D: 34, 19, 9; 1D: 4, 3, 2), or whose
/// equilibrated system has a condition number above max_condition, takes the next lower degree
/// (a box corner without ghosts at h = 3 dx: quadratics); where even quadratics fail, InputError
/// naming the particle and its neighbours (no row is left silently wrong). Stencil::method is
/// `method`.
Stencil hessian_rows(const Discretisation& disc, const StencilRequest& req, std::string method, int degree = 4,
                     Real max_condition = 1e8);

/// `method`'s stencil for `req`: method.build, or hessian_rows on the method's neighbours and
/// kernel for OperatorKind::Hessian (which no method builds itself).
Stencil build_stencil(const Method& method, const Discretisation& disc, const StencilRequest& req);

}  // namespace vrsph
