// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The generalized particle method of [IM] (METHODS §3.8.1),
// operators (2)–(4) at the particles with the reference weights of kernels/reference_weight.hpp:
//   value      Π_h v(x_i) = Σ_{j, self included} V_j v_j w_h(r_ij)             (weight pi<k>)
//   gradient   g_ij = d V_j w_h(r_ij) (x_j - x_i) / r_ij²,  difference form    (weight grad<k>)
//   laplacian  w_ij = 2d V_j w_h(r_ij) / r_ij²                                  (weight delta<k>)
//   div-a-grad w_ij = d V_j (a_i + a_j) w_h(r_ij) / r_ij² (the Morris pair form; `mean`)
// with w_h(r) = h^-d w(r/h), h the support radius. Options: weight = 1 | 2 | 3 (the family
// pi<k>/grad<k>/delta<k>, default 2: with the cubic spline and V_j = dx^d it is SPH to
// round-off, [IM](57)–(60)); volume = lattice (dx^d) | shepard (1/Σ_k pi<k>_h(r_jk)) | uniform
// (|Omega|/N) | voronoi (clipped cell measures) | vrsph (methods/particle_volumes.hpp).
// Weights 3 change sign (Hyp. 1 of order 3): their Laplacian is not an M-matrix.
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo gpm_info();
std::unique_ptr<Method> make_gpm(const MethodOptions& options);
/// The volumes V_j gpm uses for option volume= (lattice | shepard | uniform | voronoi | vrsph) and weight family.
std::vector<Real> gpm_volumes(const Discretisation& disc, const std::string& volume, const std::string& family);

}  // namespace vrsph
