// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Taylor-projection methods with a per-particle moment matrix M phi = sum_j v_j psi(j) f_j,
// phi = (f_i, grad f_i [, Hessian f_i]) (METHODS §3.3, §3.5
// [QW](2.13)–(2.19)):
//   fpm  finite particle method: test functions psi = (W, dW/dx_a [, d2W/dx_a dx_b]) of x_i
//        (Liu & Liu 2006 in 2D/3D; option variant=qw uses [QW]'s 1D (2.18) with Y_ij in the
//        third test function). Gradient from the first-order system (2.15), Laplacian as
//        the trace of the second-order Hessian.
//   kgf  kernel-gradient-free SPH (Huang et al. 2015): psi_k = W_ij q_k(x_j - x_i), a
//        weighted least-squares fit with weights v_j W_ij; no kernel derivatives.
// Sums include j = i. Both reproduce linear (order 1) / quadratic (order 2) fields exactly;
// claimed order on irregular particles: 1 for gradient and Laplacian.
// div(a grad u) has no flux form here: a_i Δ_h u + (∇a)_i·∇_h u (METHODS §3.0), with ∇a
// analytic when the request carries it, else from the same local fit.
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo fpm_info();
MethodInfo kgf_info();
std::unique_ptr<Method> make_fpm(const MethodOptions& options);
std::unique_ptr<Method> make_kgf(const MethodOptions& options);

}  // namespace vrsph
