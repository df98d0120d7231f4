// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The schemes of [SPE] (METHODS §3.7) for div(M grad u)
// with a scalar or diagonal tensor mobility M:
//   brookshaw  (27)       w_IJ = V_J Δᵀ(M_I+M_J) g_IJ / r²                 (two-point flux, monotone)
//   cb-sph     (51)       tr(A_I^-1)/d · w^B_IJ                           (corrected Brookshaw)
//   s-sph      (52)–(55)  tr(Γ_I^-1)/d · V_J [Δᵀ(M_I+M_J)g/r² - N_Iᵀ(M_I+M_J)g*]   (Schwaiger)
//   m-sph      (69)–(73)  tr(Γ̄_I^-1)/d · V_J [Δᵀ(M_I+M_J)g/r² - Ñ_Iᵀ(M_I+M_J)g*] (the new
//                         monotone scheme; Γ̄ = Γ* when admissible, else Γ, §3.7.5)
// Options: gradient = g1|g2|g3|g4 (the kernel gradient (15)–(18), default g1), volume =
// dx|shepard, anisotropy = consistent|paper (tensor mobilities only), and the singular-system
// policy of the corrected methods (max_condition, on_singular). The gradient operator is the
// corrected gradient Σ V_J (u_J - u_I) g*_IJ (23) of the same option, used by the Neumann
// rows (100). Per-particle support radii h_I enter through h̃_IJ = (h_I + h_J)/2 (26): a pair
// is a neighbour pair iff r < h̃_IJ, for both rows (gather and scatter agree).
//
// Anisotropy (METHODS R22). With a radial kernel gradient the printed pair weight tends to
// [tr(H) tr(M) + 2 tr(HM)]/(d+2), not tr(HM), when m_1 != m_2: anisotropy=paper keeps the
// printed form for reproduction. anisotropy=consistent (default for tensor mobilities) keeps
// the scheme's bracket β_IJ as the base weight and replaces the isotropic multiplier by one
// correction per direction k, c^k_IJ = β_IJ (e_Jᵀ B_k e_J + b_k·Δ_J/h_I), e_J = Δ_J/r, with
// B_k, b_k solved per particle from the discrete moment conditions Σ_J c^k Δ_J = 0 and
// Σ_J c^k Δ_J Δ_Jᵀ = E_kk; then w_IJ = Σ_k c^k_IJ (m_k,I + m_k,J). It is exact on quadratics
// for constant diagonal M on any cloud where the system is solvable, consistent for variable
// M, and reduces to the paper's weights for isotropic M on symmetric lattices. Its weights
// turn negative beyond a moderate anisotropy (docs/methods.md gives the measured bound): the
// matrix then loses its monotone structure and the BVP layer warns, naming the rows.
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo brookshaw_info();
MethodInfo cb_sph_info();
MethodInfo s_sph_info();
MethodInfo m_sph_info();
std::unique_ptr<Method> make_brookshaw(const MethodOptions& options);
std::unique_ptr<Method> make_cb_sph(const MethodOptions& options);
std::unique_ptr<Method> make_s_sph(const MethodOptions& options);
std::unique_ptr<Method> make_m_sph(const MethodOptions& options);

/// Pairs with the symmetrised support of [SPE](26): j in row i iff r_ij < (h_i + h_j)/2,
/// h_i = neighbours.radius(i) (a new search with radii (h_i + max h)/2, then filtered).
/// The schemes call it only when the radii differ; with equal radii it is `neighbours`.
NeighbourList symmetrised_pairs(const PointCloud& cloud, const NeighbourList& neighbours);

}  // namespace vrsph
