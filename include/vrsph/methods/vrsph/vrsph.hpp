// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// VRSPH — volume-reconstruction SPH ([QW] §4–5; METHODS §3.2).
//   gradient   g_ij = v_j grad_i W_ij with volumes from the gradient conditions (4.1)
//   laplacian  w_ij = v_j Y_ij with volumes from the Laplace conditions (4.2)
//   div-a-grad w_ij = 1/2 v_j (a_i + a_j) Y_ij >= 0 (Morris form with (4.2) volumes, (4.4))
// v >= 0 and a non-increasing kernel keep -L a Z-matrix with non-negative row sums
// (discrete maximum principle, [QW] Thm 5.1). Claimed order: 2 for gradient and
// Laplacian on uniform, perturbed and triangle-centroid particles (interior) and for
// the Poisson problem; not guaranteed for perturbed particles next to the boundary.
// Particles whose moment conditions cannot be met (one-sided support) keep their
// NNLS residual in Stencil::residual; callers decide whether that is an error.
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo vrsph_info();
std::unique_ptr<Method> make_vrsph(const MethodOptions& options);

}  // namespace vrsph
