// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Second derivatives by applying a first-derivative stencil twice ([AAR] (11)–(12),
// (25)–(26); METHODS §3.6):
//   aar-sph  original SPH: DB_i = sum_j (B_i - B_j) DW_i(x_j) dOmega_j, D2 = D D.
//   rkpm1    RKPM, corrected kernel K_i = C_i(x) W_i(x) with C_i linear: per-particle
//   rkpm2    constants from sum_j K_i(x_j) v_j p(x_j - x_i) = e_1, p = (1, x) or (1, x, x^2)
//            (METHODS §6 Q4: constants per particle, DK_i includes C_i').
// Extended to 2D/3D: the gradient with the kernel (corrected with the d-dimensional
// linear/quadratic basis), the Laplacian as sum_a D_a D_a and div(a grad u) as the flux
// form sum_a D_a (a D_a u). The stencils reach two neighbour rings
// (MethodInfo::stencil_rings = 2). Claimed ([AAR] §5): second order inside, not
// convergent at the boundary (boundary terms of the integration by parts).
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo aar_sph_info();
MethodInfo rkpm1_info();
MethodInfo rkpm2_info();
std::unique_ptr<Method> make_aar_sph(const MethodOptions& options);
std::unique_ptr<Method> make_rkpm1(const MethodOptions& options);
std::unique_ptr<Method> make_rkpm2(const MethodOptions& options);

}  // namespace vrsph
