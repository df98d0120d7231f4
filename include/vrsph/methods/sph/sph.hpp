// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Traditional SPH ([QW] §2.1, eqs. (2.9)–(2.12)).
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
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo sph_info();
std::unique_ptr<Method> make_sph(const MethodOptions& options);

/// Volumes used by the SPH family: dx^d or 1/sum_k W_jk.
enum class SphVolume { Spacing, Shepard };
std::vector<Real> sph_volumes(const Discretisation& disc, SphVolume mode);

/// Shepard volumes v_j = 1 / Σ_k w_j(r_jk), self (r = 0) included, for any radial weight:
/// weight_of(j) returns particle j's weight as a callable of r. A sum that is not positive (a
/// sign-changing weight) is a NumericalError naming `who` and the particle.
template <class WeightOf>
std::vector<Real> shepard_volumes(const Discretisation& disc, WeightOf&& weight_of, const std::string& who) {
  const Index n = disc.cloud.size();
  std::vector<Real> v(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
  for (Index j = 0; j < n; ++j) {
    const auto w = weight_of(j);
    Real sum = w(Real(0));
    for (Real r : disc.neighbours.distances_of(j)) sum += w(r);
    check<NumericalError>(sum > 0, who, ": the Shepard volume of particle ", j, " is not positive (the weight sum is ",
                          sum, "; a sign-changing weight needs volume=dx/lattice)");
    v[static_cast<std::size_t>(j)] = 1 / sum;
  }
  return v;
}

}  // namespace vrsph
