#pragma once
// Traditional SPH ([QW] §2.1, eqs. (2.9)–(2.12); seed 000_906375e5ed7c9bb7.txt).
//   value      <u>_i = sum_j v_j u_j W_ij (self included)
//   gradient   g_ij  = v_j grad_i W_ij                      [QW](2.10), difference form
//   laplacian  w_ij  = v_j Y_ij = -2 v_j W'(r_ij)/r_ij >= 0   [QW](2.11) (Brookshaw)
//   div-a-grad w_ij  = -v_j (a_i + a_j) W'(r_ij)/r_ij >= 0     [QW](2.12) (Morris)
// Options: volume = dx (v_j = dx^d, default; reproduces [QW]'s SPH columns) or
// shepard (v_j = 1 / sum_k W_jk, self included).
// Claimed order: O(h^2) smoothing error plus a discretisation error that does not
// vanish at fixed h/dx; gradient non-convergent and Laplacian divergent on
// randomly perturbed particles; first order for the Poisson problem with a
// truncated kernel at the boundary ([QW] Tables 2–3).
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo sph_info();
std::unique_ptr<Method> make_sph(const MethodOptions& options);

/// Volumes used by the SPH family: dx^d or 1/sum_k W_jk.
enum class SphVolume { Spacing, Shepard };
std::vector<Real> sph_volumes(const Discretisation& disc, SphVolume mode);

}  // namespace vrsph
