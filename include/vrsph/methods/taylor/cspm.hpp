// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Chen–Beraun corrective SPH (METHODS §3.4; "CSPH" in [QW];
// [AAR](16), (20)):
//   gradient   g_ij = v_j A_i^{-T} grad_i W_ij,  A_i = sum_j v_j x_ji ⊗ grad_i W_ij (full
//              matrix; equals [AAR](16) in 1D); exact for linear fields.
//   cspm         Laplacian of Chen, Beraun & Carney (1999), diagonal Hessian approximation
//                with the second kernel derivatives d2W/dx_a^2.
//   chen-beraun  [AAR](20): kernel-only second derivative
//                D2B_i = [sum v_j B_ji W_ij - DB_i sum v_j x_ji W_ij] / (1/2 sum v_j x_ji^2 W_ij);
//                extended to 2D/3D isotropically (factor d, |x_ji|^2).
//   value      Shepard interpolation.
// div(a grad u) by the rule a_i Δ_h u + (∇a)_i·∇_h u (METHODS §3.0).
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo cspm_info();
MethodInfo chen_beraun_info();
std::unique_ptr<Method> make_cspm(const MethodOptions& options);
std::unique_ptr<Method> make_chen_beraun(const MethodOptions& options);

}  // namespace vrsph
