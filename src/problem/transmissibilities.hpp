// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the negative-transmissibility, signed-row and [SPE] ξ summary of the operator
// rows, and the M-matrix test's view of balance rows with Robin data (the solve pipeline's
// row diagnostics, bvp_diagnostics.cpp).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>

namespace vrsph::detail {

// Negative off-diagonal weights of the given rows, the rows that took negative volumes (VRSPH
// boundary=signed) and the [SPE] ξ diagnostic.
inline void summarise_transmissibilities(const Stencil& L, const std::vector<char>& interior, BvpSolution& s) {
  for (Index i = 0; i < L.rows(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (!interior[si]) continue;
    Index neg = 0;
    const Real scale = std::abs(L.values[0][static_cast<std::size_t>(L.diag[si])]);
    for (Index k = L.row_begin(i); k < L.row_end(i); ++k)
      neg += L.col[static_cast<std::size_t>(k)] != i && L.values[0][static_cast<std::size_t>(k)] < -1e-12 * scale;
    s.negative_transmissibilities += neg;
    if (neg > 0 && s.negative_rows.size() < 10) s.negative_rows.push_back(i);
    if (!L.negative_volumes.empty() && L.negative_volumes[si] > 0) ++s.signed_rows;
    if (!L.xi.empty()) s.xi_max = std::isnan(s.xi_max) ? L.xi[si] : std::max(s.xi_max, L.xi[si]);
  }
}

// The warning for rows that took negative volumes (after the summary, over every rank).
inline std::string signed_rows_warning(const std::string& label, const BvpSolution& s) {
  return concat(label, ": ", s.signed_rows, " row(s) took negative volumes to meet moment conditions no non-negative "
                "volumes meet (boundary=signed; ", s.negative_transmissibilities,
                " negative off-diagonal weight(s)): -L is not an M-matrix there");
}

// The one-line warning for rows whose local problem failed or exceeds the tolerance (over
// every rank): the rows themselves are in BvpSolution::infeasible_particles, worst first.
inline std::string infeasible_rows_warning(const std::string& label, long long count, const char* what, Real worst,
                                           long long worst_particle, Real tolerance) {
  std::ostringstream r;  // three digits: a warning line, not a table
  r << std::setprecision(3) << worst;
  return concat(label, ": ", count, " ", what, " row(s) could not meet their moment conditions (worst relative "
                "residual ", r.str(), " at particle ", worst_particle, "; tolerance ", tolerance, ")");
}

// Balance rows with Robin data: the assembly adds -c_i beta_i to their diagonal (strict
// dominance), so the M-matrix test must see it too. A copy of L with that diagonal, or
// nothing when there is no such row.
inline std::optional<Stencil> with_robin_diagonal(const Stencil& L, const std::vector<char>& flux, const Field& robin) {
  if (L.wall_flux.empty() || robin.size() == 0 || robin.maxCoeff() <= 0) return std::nullopt;
  Stencil out = L;
  for (Index i = 0; i < L.rows(); ++i)
    if (flux[static_cast<std::size_t>(i)])
      out.values[0][static_cast<std::size_t>(L.diag[static_cast<std::size_t>(i)])] -=
          L.wall_flux[static_cast<std::size_t>(i)] * robin[i];
  return out;
}

}  // namespace vrsph::detail
