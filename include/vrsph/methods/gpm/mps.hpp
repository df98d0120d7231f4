// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The MPS operators as [IM] Appendix A writes them ((61)–(62), index typos fixed per
// METHODS §6 S4), at the particles:
//   gradient   g_ij = (d / n) w^MPS_h(r_ij) (x_j - x_i) / r_ij^2        (difference form)
//   laplacian  w_ij = 2d / (n lambda_h) w^MPS_h(r_ij)
// with w^MPS_h(r) = h^-d w(r/h), w normalised to integrate to 1 over R^d, n = 1/V the
// particle number density (V: `volume` = lattice dx^d or uniform |Omega|/N, [IM]
// Corollary 2), and lambda_h = ∫ |x|^2 w^MPS_h(|x|) dx = h^2 ∫ |y|^2 w(|y|) dy. (62) prints
// lambda without the h^2; with it (62) equals (4) for w(r) = r^2 w^MPS(r)/lambda and
// V = 1/n, as [IM] states, and the Laplacian is consistent.) Weights: classic
// w^MPS = 1/r - 1 (Koshizuka–Oka; unbounded at 0, outside [IM]'s class W; 2D/3D only) or
// any [IM] reference weight (pi1, pi2, pi3).
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo mps_info();
std::unique_ptr<Method> make_mps(const MethodOptions& options);

}  // namespace vrsph
